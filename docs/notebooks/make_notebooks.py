"""Write the teaching notebooks (``python docs/notebooks/make_notebooks.py``).

Each lesson is a list of cells here, so that a change to a lesson is a change to
readable text; the notebooks are written without outputs, and the tests run each
one in a fresh kernel (tests/test_notebooks.py), its slider's callback included.
"""

from pathlib import Path

import nbformat as nbf

HERE = Path(__file__).resolve().parent
SETUP = """
import matplotlib.pyplot as plt
import numpy as np

from perturb import PAPER, eq26_numbers

numbers = eq26_numbers()
print(f"natural frequency f_n0 = {numbers.f_n0_hz:.1f} Hz, "
      f"static deflection y0 = {numbers.y0_m * 1e9:.1f} nm, weight Q = {PAPER.Q_n:.3f} N")
"""
SLIDER = """
try:
    from ipywidgets import interact
except ImportError:  # the figure above is the slider's at its first value
    print("pip install ipywidgets (or .[notebooks]) for the slider")
else:
    interact({function}, {ranges})
"""

LESSONS = {
    "1-linear-and-nonlinear": [
        ("md", """
# 1. A linear and a non-linear contact

A slider rests on a slideway under its own weight; the rough contact between them acts
as one non-linear spring and damper, stiffer the more it is pressed, and it can open.
This lesson sets the contact beside its linearisation about the static deflection y0:
same natural frequency, same damping, very different resonance curves.
"""),
        ("code", SETUP),
        ("md", """
The linearised contact (`LINEAR`: a linear spring and damper about y0, no loss of
contact) and the full one, swept up and down through the primary resonance. Move the
force amplitude: the linear peak only grows, the full one bends towards low
frequencies, and its up and down sweeps part between two jumps.
"""),
        ("code", """
from numerics import sweep
from perturb import FULL, LINEAR, ContactModel


def compare_contacts(pa_frac=0.05):
    \"\"\"Sweeps up and down at P_a / Q = pa_frac, linear and full contact.\"\"\"
    grid = np.linspace(1250.0, 1600.0, 36)
    for effects, style in ((LINEAR, "--"), (FULL, "-")):
        result = sweep(grid, pa_frac, direction="both", model=ContactModel(effects=effects))
        for run in result.runs:
            plt.plot(run.frequency_hz, run.app_m * 1e9, style,
                     label=f"{'linear' if effects is LINEAR else 'full'}, {run.direction}")
    plt.xlabel("excitation frequency f_e [Hz]")
    plt.ylabel("App [nm]")
    plt.title(f"P_a = {pa_frac:g} Q")
    plt.legend()
    plt.show()
    return result


full = compare_contacts(0.05)
"""),
        ("code", SLIDER.format(function="compare_contacts", ranges="pa_frac=(0.01, 0.2, 0.01)")),
        ("md", """
At half its weight the full contact opens for part of every period: y, the contact's
deflection (positive in compression), falls below zero and the slider flies.
"""),
        ("code", """
from numerics import simulate

run = simulate([1200.0], 0.5 * PAPER.Q_n, periods=300, record="history", record_periods=2)
plt.plot(run.history_phase, run.history_y_m[0] * 1e9)
plt.axhline(0.0, color="k", lw=0.8)
plt.xlabel("time [excitation periods]")
plt.ylabel("y [nm]  (below 0: in flight)")
plt.title("P_a = 0.5 Q, 1200 Hz: the slider bounces")
plt.show()
"""),
    ],
    "2-superharmonics": [
        ("md", """
# 2. Superharmonic resonances and the harmonics behind them

A non-linear spring turns a harmonic force into a response with harmonics. Where the
m-th harmonic meets the natural frequency, f_e near f_n0 / m, it is itself resonant: a
superharmonic resonance, a peak below the primary one.
"""),
        ("code", SETUP),
        ("code", """
from numerics import sweep

grid = np.linspace(400.0, 1600.0, 121)
for pa_frac in (0.05, 0.15):
    run = sweep(grid, pa_frac, direction="up").runs[0]
    plt.semilogy(run.frequency_hz, run.app_m * 1e9, label=f"P_a = {pa_frac:g} Q")
for m in (1, 2, 3):
    plt.axvline(numbers.f_n0_hz / m, color="grey", lw=0.6)
plt.xlabel("excitation frequency f_e [Hz]")
plt.ylabel("App [nm]")
plt.title("Peaks at f_n0 / m (grey)")
plt.legend()
plt.show()
"""),
        ("md", """
The harmonics of y over one period of the steady state, at a chosen f_e: near 740 Hz
the second harmonic, at twice f_e, is close to f_n0 and stands out.
"""),
        ("code", """
from numerics import simulate
from numerics.scenes import harmonic_amplitudes


def spectrum(frequency_hz=740.0, pa_frac=0.15):
    \"\"\"The harmonics of the steady response at f_e, P_a / Q.\"\"\"
    run = simulate([frequency_hz], pa_frac * PAPER.Q_n, periods=600, record="history",
                   record_periods=1)
    amplitudes = harmonic_amplitudes(run.history_y_m[0])[1:9]
    plt.bar(np.arange(1, 9), amplitudes * 1e9)
    plt.xlabel("harmonic k (frequency k f_e)")
    plt.ylabel("amplitude [nm]")
    plt.title(f"f_e = {frequency_hz:g} Hz, P_a = {pa_frac:g} Q")
    plt.show()
    return amplitudes


amplitudes = spectrum(740.0, 0.15)
print(f"second over first harmonic: {amplitudes[1] / amplitudes[0]:.2f}")
"""),
        ("code", SLIDER.format(function="spectrum",
                                ranges="frequency_hz=(400.0, 1600.0, 10.0), "
                                       "pa_frac=(0.01, 0.3, 0.01)")),
    ],
    "3-jumps-folds-continuation": [
        ("md", """
# 3. Jumps, folds and continuation

A bent peak has two stable motions over a band of frequencies. A sweep stays on the
one it came from and jumps where that branch ends, at a fold. Continuation follows
the branch through its folds, the unstable middle part included, with its Floquet
multipliers at every point.
"""),
        ("code", SETUP),
        ("code", """
from numerics import continue_orbits, sweep


def jumps_and_folds(pa_frac=0.05):
    \"\"\"Sweeps up and down (dots) over the continued branch (stable solid, unstable
    dashed), and its folds.\"\"\"
    grid = np.linspace(1250.0, 1600.0, 36)
    for run in sweep(grid, pa_frac, direction="both").runs:
        plt.plot(run.frequency_hz, run.app_m * 1e9, "o" if run.direction == "up" else "x",
                 label=f"sweep {run.direction}")
    walk = continue_orbits(pa_frac, 1250.0, 1600.0)
    for branch in walk.branches:
        app = branch.app_m * 1e9
        plt.plot(branch.frequency_hz, np.where(branch.stable, app, np.nan), "k-")
        plt.plot(branch.frequency_hz, np.where(branch.stable, np.nan, app), "k--")
    for fold in walk.folds():
        plt.plot(fold.frequency_hz, fold.app_m * 1e9, "rs")
    plt.xlabel("excitation frequency f_e [Hz]")
    plt.ylabel("App [nm]")
    plt.title(f"P_a = {pa_frac:g} Q: folds at "
              + ", ".join(f"{fold.frequency_hz:.1f}" for fold in walk.folds()) + " Hz")
    plt.legend()
    plt.show()
    return walk


walk = jumps_and_folds(0.05)
print(walk)
"""),
        ("code", SLIDER.format(function="jumps_and_folds", ranges="pa_frac=(0.01, 0.1, 0.005)")),
        ("md", """
Below some force the peak does not bend far enough to fold: the two folds are born
together at a cusp, the least force at which the primary resonance is bistable.
"""),
        ("code", """
from numerics import fold_curves

curves = fold_curves(1300.0, 1500.0, 0.03, 0.05)
for curve in curves.fold_curves:
    plt.plot(curve.frequency_hz, curve.pa_frac, "k-")
for cusp in curves.cusps:
    plt.plot(cusp.frequency_hz, cusp.pa_frac, "r^", label=f"cusp: {cusp.pa_frac:.4f} Q")
plt.xlabel("excitation frequency f_e [Hz]")
plt.ylabel("P_a / Q")
plt.title("Where the primary resonance is bistable")
plt.legend()
plt.show()
"""),
    ],
    "4-series": [
        ("md", """
# 4. The series, by hand and by the engine

The paper derives a Lindstedt-type series of the equation in contact by hand, to
eps^4. The engine derives it to any order, for any contact, and prints it in the
paper's names; here the series' resonance curve is set beside the simulator's.
"""),
        ("code", SETUP),
        ("code", """
from perturb import derivation_text, derive

series = derive(2, truncation="paper")  # Eq. 2.6's series, the paper's own
print(derivation_text(series)[:1500])
"""),
        ("code", """
from numerics import sweep
from perturb import frequency_response


def series_and_simulator(order=4, pa_frac=0.05):
    \"\"\"The order-N series' response (valid points solid) beside the simulator's sweeps.\"\"\"
    grid = np.linspace(1250.0, 1600.0, 36)
    response = frequency_response(np.linspace(1250.0, 1600.0, 176), pa_frac, order)
    for branch in response.branches:
        plt.plot(branch.frequency_hz, np.where(branch.valid, branch.app_m * 1e9, np.nan), "-")
    for run in sweep(grid, pa_frac, direction="both").runs:
        plt.plot(run.frequency_hz, run.app_m * 1e9, "ko", ms=3)
    plt.xlabel("excitation frequency f_e [Hz]")
    plt.ylabel("App [nm]")
    plt.title(f"order {order} against RK4 (dots), P_a = {pa_frac:g} Q")
    plt.show()
    return response


response = series_and_simulator(4, 0.05)
"""),
        ("code", SLIDER.format(function="series_and_simulator",
                                ranges="order=(0, 8, 1), pa_frac=(0.01, 0.1, 0.01)")),
    ],
}


def write() -> None:
    for name, cells in LESSONS.items():
        notebook = nbf.v4.new_notebook(metadata={"kernelspec": {
            "name": "python3", "display_name": "Python 3", "language": "python"}})
        for kind, text in cells:
            make = nbf.v4.new_markdown_cell if kind == "md" else nbf.v4.new_code_cell
            notebook.cells.append(make(text.strip()))
        nbf.write(notebook, HERE / f"{name}.ipynb")


if __name__ == "__main__":
    write()
