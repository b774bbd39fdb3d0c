"""Benchmarks: each bench_*.py has a main() that prints figures beside baselines."""
