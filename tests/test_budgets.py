"""Every option that sizes the work is checked where it enters, before any work: a value
is taken only up to a limit measured to stay within time and memory, and refused past
it with exit status 2 and one line naming the option.

Hypothesis feeds each option sizes from 1 to 10^12. Refusal is checked by running the
command's parser (argparse types) and the API's own checks, which raise before any
allocation; an accepted size is held to the measured limit (the tests that measure the
limits: tests/test_cli_errors.py, tests/test_backbone.py). Then whole commands run in
new processes on sizes spread over the orders of magnitude: a refused size exits 2 at
once, an accepted one finishes, or is still working when its window closes, within
2 GiB (the peak at each limit, run to the end: tests/benchmarks/bench_limits.py)."""

import argparse
import contextlib
import io
import sys

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from numerics import cli
from numerics.backbone.exact import MAX_POINTS
from numerics.cli._steady import MAX_STEADY_STEPS
from numerics.steady.multistability import MAX_LANES
from numerics.steady.shooting import MAX_STEPS
from numerics.steady.sweeps import MAX_STATES
from perturb.__main__ import build_parser as perturb_parser
from perturb.series.slow_orders import SLOW_ORDERS
from tests._peak_memory import BUDGET_BYTES, peak_memory

SIZES = st.integers(1, 10**12)


def parses(parser: argparse.ArgumentParser, argv: list[str]) -> bool:
    """Whether ``argv`` parses; a refusal must be argparse's (exit 2), never another
    (its message on stderr is kept out of the test's output)."""
    try:
        with contextlib.redirect_stderr(io.StringIO()):
            parser.parse_args(argv)
    except SystemExit as exit_:
        assert exit_.code == 2
        return False
    return True


@settings(max_examples=60, deadline=None)
@given(size=SIZES, option=st.sampled_from([
    (["sweep", "--points"], 2, MAX_STATES), (["sweep", "--steps"], 4, MAX_STEADY_STEPS),
    (["attractors", "--fe", "1000", "--pa-frac", "0.1", "--steps"], 4, MAX_STEADY_STEPS),
    (["continue", "--pa-frac", "0.05", "--steps"], 4, MAX_STEPS),
    (["backbone", "--points"], 1, MAX_POINTS),
]))
def test_numerics_sizes_are_taken_up_to_their_limit(size, option):
    argv, least, limit = option
    assert parses(cli.build_parser(), [*argv, str(size)]) == (least <= size <= limit)


@settings(max_examples=40, deadline=None)
@given(cells=st.tuples(st.integers(2, 10**12), st.integers(2, 10**12)))
def test_an_atlas_is_refused_past_its_lanes_before_any_work(cells):
    from numerics import atlas

    lanes = cells[0] * cells[1] * 98  # the command's default initial states
    if lanes <= MAX_LANES:
        return  # taken (the limit's time: tests/test_cli_errors.py)
    with pytest.raises(ValueError, match="more than the limit"):
        atlas(400.0, 800.0, 0.1, 0.5, grid=cells, workers=1)


@settings(max_examples=40, deadline=None)
@given(order=st.integers(0, 10**6), command=st.sampled_from([
    (["derive"], 24), (["backbone"], 100),
    (["response", "--pa-frac", "0.05", "--points", "3"], 24)]))
def test_an_order_past_its_limit_is_refused_before_any_work(order, command):
    from perturb.series.slow_orders import check_slow_order

    argv, limit = command
    args = perturb_parser().parse_args([argv[0], "--order", str(order), *argv[1:]])
    if order <= limit:
        assert check_slow_order(args.order, argv[0], "paper") == order
    else:  # (tests/test_cli_errors.py runs each command past its limit)
        with pytest.raises(ValueError, match=f"is above {limit}"):
            check_slow_order(args.order, argv[0], "paper", allow_slow=args.allow_slow)


#: Sizes spread over the orders of magnitude, 0 to 10^12.
SPREAD = st.one_of(st.just(0), st.integers(0, 11).flatmap(
    lambda e: st.integers(10**e, 10**(e + 1))))
_NUMERICS, _PERTURB = [sys.executable, "-m", "numerics"], [sys.executable, "-m", "perturb"]
#: (the command with the size in it, least, limit): cheap commands apart from the size.
RUNS = {
    "sweep --points": (lambda n: [*_NUMERICS, "sweep", "--points", n, "--fmin", "1000",
                                  "--fmax", "1100", "--pa-frac", "0.05", "--direction", "up"],
                       2, MAX_STATES),
    "sweep --steps": (lambda n: [*_NUMERICS, "sweep", "--steps", n, "--points", "2", "--fmin",
                                 "1000", "--fmax", "1001", "--pa-frac", "0.05"],
                      4, MAX_STEADY_STEPS),
    "continue --steps": (lambda n: [*_NUMERICS, "continue", "--steps", n, "--pa-frac", "0.05",
                                    "--fmin", "1000", "--fmax", "1005"], 4, MAX_STEPS),
    "backbone --points": (lambda n: [*_NUMERICS, "backbone", "--points", n], 1, MAX_POINTS),
    "derive --order": (lambda n: [*_PERTURB, "derive", "--order", n], 0,
                       SLOW_ORDERS["derive", "polynomial law"][0]),
    "response --order": (lambda n: [*_PERTURB, "response", "--order", n, "--points", "3",
                                    "--pa-frac", "0.05"], 0,
                         SLOW_ORDERS["response", "polynomial law"][0]),
}
#: Seconds a command may work before it is stopped: its memory is measured until then
#: (the arrays that an option sizes are allocated first); the peak of each limit run to
#: its end is bench_limits'.
WINDOW_S = 6.0


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(size=SPREAD, name=st.sampled_from(sorted(RUNS)))
def test_a_whole_command_finishes_within_its_budget_or_is_refused(size, name):
    command, least, limit = RUNS[name]
    code, peak, seconds = peak_memory([*command(str(size)), "--quiet"], WINDOW_S)
    if least <= size <= limit:
        assert code in (0, None), (name, size, code)  # done, or working when stopped
        assert peak < BUDGET_BYTES, (name, size, peak)
    else:
        assert code == 2 and seconds < WINDOW_S, (name, size, code, seconds)
