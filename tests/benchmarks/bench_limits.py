"""Memory at the limits: every option that sizes the work, at the largest value it
accepts, run in a new process; its peak resident memory beside the budget of 2 GiB.

A command still working when its window closes is stopped there and says so: its
peak is that of the window (the arrays an option sizes are allocated before the work;
the walks and the backbone keep a bounded amount while they run)."""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

from numerics.backbone.exact import MAX_POINTS
from numerics.cli._steady import MAX_STEADY_STEPS
from numerics.continuation.walk import MAX_WALK_POINTS
from numerics.steady.census import DEFAULT_GRID
from numerics.steady.multistability import MAX_LANES
from numerics.steady.shooting import MAX_STEPS
from numerics.steady.sweeps import MAX_STATES
from perturb.model.effects import MAX_TAYLOR_DEGREE
from perturb.series.slow_orders import SLOW_ORDERS
from tests._peak_memory import BUDGET_BYTES, peak_memory

from ._timing import header

_NUMERICS = [sys.executable, "-m", "numerics"]
_PERTURB = [sys.executable, "-m", "perturb"]
#: Seconds each command may run before it is stopped and its peak so far reported.
WINDOW_S = 240.0

_TAYLOR_SCENE = f"""
effects = {{spring = "taylor", taylor_degree = {MAX_TAYLOR_DEGREE}}}
[excitation]
pa_frac = 0.05
frequency_hz = {{start = 1000.0, stop = 1400.0, count = 9}}
[study]
kind = "sweep"
"""


def cases(folder: Path) -> list[tuple[str, list[str]]]:
    """(what, the command) at each limit."""
    scene = folder / "taylor.toml"
    scene.write_text(_TAYLOR_SCENE)
    amplitudes = [f"{0.001 * (k + 1):g}" for k in range(500)]
    states = len(DEFAULT_GRID["y_over_y0"]) * len(DEFAULT_GRID["v_over_omega0_y0"])  # a cell's
    side = int((MAX_LANES / states) ** 0.5)
    return [
        (f"sweep --steps {MAX_STEADY_STEPS}", [*_NUMERICS, "sweep", "--steps",
                                               str(MAX_STEADY_STEPS),
                                        "--points", "2", "--fmin", "1000", "--fmax", "1001",
                                        "--pa-frac", "0.05", "--quiet"]),
        (f"sweep, {MAX_STATES} states (1000 points x 500 P_a x 2)",
         [*_NUMERICS, "sweep", "--points", str(MAX_STATES // 1000), "--fmin", "500",
          "--fmax", "1500", "--pa-frac", *amplitudes, "--quiet"]),
        (f"attractors --steps {MAX_STEADY_STEPS}",
         [*_NUMERICS, "attractors", "--fe", "1000", "--pa-frac", "0.1", "--steps",
          str(MAX_STEADY_STEPS), "--quiet"]),
        (f"continue --steps {MAX_STEPS}", [*_NUMERICS, "continue", "--pa-frac", "0.05",
                                           "--fmin", "1000", "--fmax", "1010", "--steps",
                                           str(MAX_STEPS), "--quiet"]),
        (f"backbone --points {MAX_POINTS}", [*_NUMERICS, "backbone", "--points",
                                              str(MAX_POINTS), "--quiet"]),
        (f"atlas {side} x {side} cells ({side * side * states} lanes), 1 worker",
         [*_NUMERICS, "atlas", "--grid", str(side), str(side), "--workers", "1", "--quiet"]),
        *_orders(),
        (f"scene, Taylor spring of degree {MAX_TAYLOR_DEGREE}",
         [*_NUMERICS, "scene", str(scene), "--quiet"]),
    ]


def _orders() -> list[tuple[str, list[str]]]:
    """Each series command at its largest order, for a polynomial law (the paper's
    contact) and a power law (m2 = 1.5, l = 0.5)."""
    other = ["--set", "m2=1.5", "--set", "l=0.5"]
    extra = {"derive": [], "backbone": [], "response": ["--pa-frac", "0.05", "--points", "3"]}
    out = []
    for (work, kind), (order, _) in SLOW_ORDERS.items():
        argv = [*_PERTURB, work, "--order", str(order), *extra[work], "--quiet"]
        out.append((f"perturb {work} --order {order} ({kind})",
                    argv + (other if kind == "power law" else [])))
    return out


def main() -> None:
    header(f"peak memory at each limit, new process (window {WINDOW_S:g} s; "
           f"walks keep at most {MAX_WALK_POINTS} points)")
    with tempfile.TemporaryDirectory() as folder:
        for what, argv in cases(Path(folder)):
            code, peak, seconds = peak_memory(argv, WINDOW_S)
            ended = f"exit {code}" if code is not None else "stopped: still working"
            print(f"{what:<52} {peak / 2**20:>9.0f} MB {BUDGET_BYTES / 2**20:>9.0f} MB "
                  f"{peak / BUDGET_BYTES:>8.2f}x  ({ended}, {seconds:.1f} s)", flush=True)


if __name__ == "__main__":
    main()
