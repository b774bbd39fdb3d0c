"""Start-up (issue 12, item 1): a command whose cache is warm does not import sympy.

Regression: every `python -m numerics` command imported sympy, scipy.optimize and
the scenes with the packages, and solved for y0 and derived Eq. 2.6's numbers with
sympy in every process: 1.4 s for `info`'s seven numbers, 3.4 s for the Fig. 2 + 3
sweep whose job takes 0.5 s. The packages now import their names at first use
(PEP 562), and the model's numbers and kernels are read from the cache on disk.
Each check runs the real command in a new process, as a user does.
"""

import json
import os
import subprocess
import sys

import pytest
import sympy as sp

#: A command (``python -m PACKAGE ARGS``: PACKAGE, then ARGS) run in this process, then
#: the heavy modules it imported, on stderr.
WHICH_MODULES = """
import runpy, sys
package = sys.argv[1]
sys.argv = [package, *sys.argv[2:]]
try:
    runpy.run_module(package, run_name="__main__", alter_sys=True)
except SystemExit as done:
    assert not done.code, done.code
heavy = ("sympy", "scipy", "scipy.optimize", "numba", "matplotlib")
print("imported:", *(m for m in heavy if m in sys.modules), file=sys.stderr)
"""

#: What each command may not import once the cache is warm (numba imports
#: scipy.linalg when it starts, so the simulating commands do have scipy).
COMMANDS = {
    "info": (["info"], {"sympy", "scipy", "numba", "matplotlib"}),
    "attractors": (["attractors", "--pa-frac", "0.5", "--fe", "490", "--quiet"],
                   {"sympy", "scipy.optimize", "matplotlib"}),
    "sweep": (["sweep", "--pa-frac", "0.05", "--points", "3", "--direction", "up", "--quiet"],
              {"sympy", "scipy.optimize", "matplotlib"}),
    # A scene that draws a figure: matplotlib, but neither sympy nor scipy.optimize (a
    # review found the series' route and the backbone's figure importing them).
    "scene": (["scene", "numerics/scenes/examples/bouncing.toml", "--quiet", "--out",
               "{tmp}"], {"sympy", "scipy.optimize"}),
    # The analytic response with its order's kernels built: no derivation.
    "perturb response": (["--perturb", "response", "--pa-frac", "0.05", "--points", "5",
                          "--quiet"], {"sympy", "scipy.optimize", "matplotlib"}),
}


def imported(args: list[str], env: dict | None = None) -> set[str]:
    """The heavy modules that ``python -m numerics ARGS`` (``--perturb`` first: ``python -m
    perturb``) imported."""
    package = "perturb" if args[:1] == ["--perturb"] else "numerics"
    args = args[1:] if package == "perturb" else args
    done = subprocess.run([sys.executable, "-c", WHICH_MODULES, package, *args],
                          capture_output=True, text=True, check=True, env=env)
    return set(done.stderr.strip().splitlines()[-1].split()) - {"imported:"}


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_a_warm_command_does_not_import_sympy(name, tmp_path):
    args, forbidden = COMMANDS[name]
    args = [arg.replace("{tmp}", str(tmp_path)) for arg in args]
    if name == "perturb response":
        from perturb.response.codegen import series_kernels

        series_kernels(6)  # built once per cache: the warm case
    imported(args)  # fills the cache when it is empty (that run may import anything)
    assert not imported(args) & forbidden


def test_a_cold_cache_does_import_sympy(tmp_path):
    # The negative control of the test above: without the cached numbers, `info`
    # derives them with sympy, and the check sees it.
    env = os.environ | {"CONTACT_RESONANCES_CACHE": str(tmp_path)}
    assert "sympy" in imported(["info"], env)
    assert "sympy" not in imported(["info"], env)


def test_importing_the_packages_imports_nothing_heavy():
    code = ("import sys, perturb, perturb.common, numerics, numerics.cli; "
            "print(' '.join(m for m in ('sympy', 'scipy', 'numba', 'matplotlib', 'tqdm') "
            "if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert done.stdout.split() == []


@pytest.mark.parametrize("package", ["perturb", "numerics", "numerics.plots"])
def test_every_public_name_is_importable(package):
    # The names are imported at first use: each must still be found, and listed.
    code = (f"import {package}\nfor name in {package}.__all__:\n"
            f"    exec(f'from {package} import {{name}}')\n"
            f"assert set({package}.__all__) <= set(dir({package}))")
    subprocess.run([sys.executable, "-c", code], check=True)


def test_a_result_file_loads_in_a_new_process(tmp_path):
    # load() finds the class of a lazily imported package by its name, and a nested
    # result's class (SweepRun) by importing the rest.
    from numerics import sweep

    result = sweep([1300.0, 1400.0], 0.05, direction="up")
    result.to_json(tmp_path / "sweep.json")
    result.runs[0].to_json(tmp_path / "run.json")
    code = ("import sys\nfrom perturb import common\nfor path in sys.argv[1:]:\n"
            "    print(type(common.load(path)).__name__)")
    done = subprocess.run([sys.executable, "-c", code, str(tmp_path / "sweep.json"),
                           str(tmp_path / "run.json")], capture_output=True, text=True,
                          check=True)
    assert done.stdout.split() == ["Sweep", "SweepRun"]
    assert json.loads((tmp_path / "sweep.json").read_text())["kind"] == "Sweep"


def test_the_static_deflection_in_closed_form_solves_the_equilibrium():
    # y0 is written in closed form (sympy.solve took 0.3 s of every cold start):
    # substituted back it balances the weight, S c_n y0^m2 = M g, and it is the
    # root sympy.solve finds.
    from perturb import ContactModel
    from perturb import symbols as s

    y0 = ContactModel().static_deflection
    assert sp.simplify(s.S * s.c_n * y0**s.m2 - s.M * s.g) == 0
    assert sp.solve(sp.Eq(s.S * s.c_n * s.y**s.m2, s.M * s.g), s.y) == [y0]
