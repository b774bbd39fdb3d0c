"""Generate and compile the simulator for a model's chosen effects.

The acceleration of Eq. 2.4 is taken from ``perturb.ContactModel``,
lambdified, and written, with the kernels of ``kernel_template.py``, into
a module file in the cache folder (``perturb.cache``); numba compiles it and
caches the machine code beside it, so that a second run (or a second process)
pays nothing. The file's key is made of the model and the source files that
shape the kernels, so finding it needs no sympy: a process that has its kernels
cached imports neither sympy nor anything that derives.
"""

from __future__ import annotations

import inspect
import threading
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING

from perturb import ContactModel
from perturb.cache import (
    MODEL_SOURCES,
    CacheWarning,
    cache_dir,
    cache_key,
    intact,
    load_generated,
    machine_code_index,
    usable_cache_dir,
)

if TYPE_CHECKING:
    import sympy as sp

__all__ = ["compiled_kernels", "kernels_built", "acceleration_source", "cache_dir", "CacheWarning"]

_TEMPLATE = Path(__file__).with_name("kernel_template.py")
#: The compiled sweep, appended after the kernels (it reads the steady-state engine's
#: constants, ``numerics.steady.shooting``, and its default options,
#: ``numerics.steady.options``).
_SWEEP_TEMPLATE = Path(__file__).with_name("sweep_template.py")
#: The files whose code shapes a kernel module (a change to it generates the module again;
#: an edit of a comment or docstring does not: ``cache_key``).
KERNEL_SOURCES = (*MODEL_SOURCES, Path(__file__), _TEMPLATE, _SWEEP_TEMPLATE,
            Path(__file__).parents[1] / "steady" / "shooting.py",
            Path(__file__).parents[1] / "steady" / "options.py",
            # the sweep template freezes common.Status's values into the machine code
            Path(__file__).parents[2] / "perturb" / "common" / "_status.py")
_LOADED: dict[tuple, ModuleType] = {}
_LOCK = threading.Lock()


def _force_symbol() -> sp.Symbol:
    """The argument that replaces the drive P(t) in the generated acceleration."""
    import sympy as sp

    return sp.Symbol("force", real=True)


def _guard_contact_branch(expr: sp.Expr, y: sp.Symbol) -> sp.Expr:
    """Write y as max(y, 0) inside the in-contact branch of every Piecewise.

    Compiled code may evaluate both branches of a conditional; with the guard it
    never raises a negative number to a fractional power (m2 = 1.5, l = 0.5).
    """
    import sympy as sp

    def guard(piecewise: sp.Piecewise) -> sp.Piecewise:
        return sp.Piecewise(*[
            (branch.subs(y, sp.Max(y, 0)) if condition == (y > 0) else branch, condition)
            for branch, condition in piecewise.args
        ])

    return expr.replace(lambda e: isinstance(e, sp.Piecewise), guard)


#: Where a contact side's law holds y when y is below it (and past the switch).
TINY_Y = 1e-300


def _one_side(expr: sp.Expr, y: sp.Symbol, contact: bool) -> sp.Expr:
    """The law of one side of the switch at y = 0: every Piecewise replaced by its
    in-contact branch (guarded, so that it extends past y = 0 with y held at TINY_Y) or by its
    out-of-contact branch. Events integrate each side with its own law, up to the
    switch and a little past it while they locate it."""
    import sympy as sp

    def pick(piecewise: sp.Piecewise) -> sp.Expr:
        for branch, condition in piecewise.args:
            if (condition == (y > 0)) == contact:
                # y held at TINY_Y: a law's derivative that is infinite at y = 0 (l < 1)
                # stays finite there.
                return branch.subs(y, sp.Max(y, TINY_Y)) if contact else branch
        raise ValueError(f"a law switches on another condition than y > 0: {piecewise}")

    return expr.replace(lambda e: isinstance(e, sp.Piecewise), pick)


def side_laws(expr: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """``expr`` by the law of each side of y = 0: (in contact, in flight), as the kernels
    integrate them near a switch (``_one_side``); both ``expr`` where nothing switches."""
    from perturb import symbols

    return tuple(_one_side(expr, symbols.y, contact) for contact in (True, False))


def _lambdified_source(name: str, expr, model: ContactModel) -> str:
    import sympy as sp

    from perturb import symbols

    function = sp.lambdify((symbols.y, symbols.v, _force_symbol()), expr, modules="math",
                           cse=True)
    body = inspect.getsource(function).replace(function.__name__, name, 1)
    return f"@numba.njit(cache=True, inline='always')\n{body}\n\n"


def acceleration_source(model: ContactModel) -> str:
    """Python source of the generated right-hand side of the model, via lambdify.

    ``acceleration(y, v, force)`` is Eq. 2.4 for the chosen effects, and
    ``acceleration_partials(y, v, force)`` its derivatives by y, by v and by the force
    (for the monodromy matrix and the derivative in P_a), all differentiated by sympy.
    The drive P(t) is replaced by the argument ``force`` (the kernels tabulate it), and
    every parameter by its value.
    """
    import sympy as sp

    from perturb import symbols

    accel = model.numeric_acceleration(_force_symbol())
    partials = [sp.diff(accel, s) for s in (symbols.y, symbols.v, _force_symbol())]
    guard = lambda e: _guard_contact_branch(e, symbols.y)  # noqa: E731
    switches = accel.has(sp.Piecewise)
    sides = []
    # The contact side's law holds y at TINY_Y below it, so its derivative by y is 0
    # there (and not the law's, which is infinite at y = 0 where l < 1).
    held = sp.Piecewise((1, symbols.y > TINY_Y), (0, True)) if switches else 1
    for contact, side in ((True, "contact"), (False, "flight")):
        law = lambda e: _one_side(e, symbols.y, contact) if switches else guard(e)  # noqa: E731,B023
        by_y, by_v, by_force = map(law, partials)
        sides.append(_lambdified_source(f"acceleration_{side}", law(accel), model)
                     + _lambdified_source(f"acceleration_partials_{side}",
                                          (by_y * held if contact else by_y, by_v, by_force),
                                          model))
    # lambdify's "math" namespace: its source names math functions unqualified.
    return (
        f"from math import *  # noqa: F403\n\n# Eq. 2.4 for {model!r}\n"
        f"# Whether the laws switch at y = 0 (contact loss): steps across it are split there.\n"
        f"SWITCHES = {switches}\n\n"
        + _lambdified_source("acceleration", guard(accel), model)
        + _lambdified_source("acceleration_partials", tuple(map(guard, partials)), model)
        + "".join(sides)
    )


def _module_source(model: ContactModel) -> str:
    template = _TEMPLATE.read_text()
    imports_end = template.index("# fmt: off")
    # Template imports first, then the generated acceleration, then the kernels.
    return (
        "# Generated by numerics.kernels.codegen: do not edit.\n"
        + template[:imports_end]
        + acceleration_source(model)
        + "\n\n"
        + template[imports_end:]
        + "\n\n"
        + _SWEEP_TEMPLATE.read_text()
    )


def _cache_key(model: ContactModel) -> str:
    """A key for the model's kernels that needs no sympy: the parameters and effects,
    sympy's release, and the code of every file that shapes the generated source."""
    return cache_key((model.parameters, model.effects), KERNEL_SOURCES)


def compiled_kernels(model: ContactModel) -> ModuleType:
    """The compiled kernel module of ``model`` (generated once, then cached)."""
    memo = (model.parameters, model.effects)
    with _LOCK:
        if memo not in _LOADED:
            _LOADED[memo] = _load(_cache_key(model), model)
        return _LOADED[memo]


#: (cache folder, parameters, effects) whose driver was found built in this process, and
#: the index file found (a stat of it is cheap; another process may remove it).
_DRIVERS_BUILT: dict[tuple, Path] = {}


def sweep_driver_built(model: ContactModel) -> bool:
    """Whether the compiled sweep driver of ``model`` is in the cache (numba's index file
    of ``sweep_lanes`` beside the module): compiling it takes tens of seconds, once
    (bench_sweep's cold start row). A positive answer is kept for the process (the
    look-up hashes the sources and lists a folder of thousands of files: some 10 ms)."""
    memo = (cache_dir(), model.parameters, model.effects)
    if memo in _DRIVERS_BUILT and _DRIVERS_BUILT[memo].exists():
        return True
    _DRIVERS_BUILT.pop(memo, None)
    path = usable_cache_dir() / f"kernel_{_cache_key(model)}.py"
    index = machine_code_index(path, "sweep_lanes")
    if index is None or not intact(path):
        return False
    _DRIVERS_BUILT[memo] = index
    return True


def forget_sweep_driver(model: ContactModel) -> None:
    """Remove the compiled sweep driver's machine code of ``model`` from the cache (numba's
    files of ``sweep_lanes``), so that it is compiled again when next asked for."""
    _DRIVERS_BUILT.pop((cache_dir(), model.parameters, model.effects), None)
    path = usable_cache_dir() / f"kernel_{_cache_key(model)}.py"
    for stale in path.parent.glob(f"__pycache__/{path.stem}.sweep_lanes-*"):
        stale.unlink(missing_ok=True)


#: The kernels compiled when the module is first loaded; the others (the Lyapunov
#: exponent's and continuation's ``shoot_jacobian``, a few seconds of a model's some
#: 20 s) at their first call, which a run that meets no lane that never settles and
#: continues nothing (`make paper`) does not make.
EAGER_KERNELS = ("advance_periods", "record_periods", "shoot_periods", "strobe_periods",
                 "acceleration_batch")


def kernels_built(model: ContactModel) -> bool:
    """Whether ``model``'s kernel module is in the cache, whole, with numba's machine code
    of every kernel of ``EAGER_KERNELS`` (loading it then compiles nothing)."""
    path = usable_cache_dir() / f"kernel_{_cache_key(model)}.py"
    return intact(path) and all(machine_code_index(path, name) is not None
                                for name in EAGER_KERNELS)


def _compiled_before(module: ModuleType, name: str) -> bool:
    """Whether numba's cache holds machine code of the kernel ``name`` of ``module``."""
    return machine_code_index(Path(module.__file__), name) is not None


def _smoke(module: ModuleType) -> None:
    """Call every kernel once on one lane, with the argument types of the real calls:
    those of ``EAGER_KERNELS``, and the others if numba's cache holds them.

    numba loads a kernel's machine code from its cache at the first call, not at
    import: a truncated or garbled cache file shows only here (and is then rebuilt
    by ``_load``). Matching the real types, the calls load what the real ones use. A
    kernel never compiled has no cache file to be garbled: it compiles at its first
    call.
    """
    import numpy as np

    lane = np.ones(1)
    drive = np.cos(np.pi * np.arange(9) / 4)  # 4 steps per period, as drive_table(4)
    drive.flags.writeable = False
    failed = np.full(1, -1, dtype=np.int64)
    state = [np.full(1, 1e-7), np.zeros(1), np.full(1, 1e-4), np.zeros(1)]  # y, v, dt, P_a
    module.advance_periods(*[a.copy() for a in state], drive, 1, failed.copy(), lane)
    module.record_periods(
        *[a.copy() for a in state], drive, 1, failed.copy(), 0, np.empty(1), np.empty(1),
        np.empty((1, 0)), np.empty((1, 0)), np.empty((1, 0), dtype=np.int8),
        np.zeros(1, dtype=np.int64), np.empty((1, 0)), np.empty((1, 0)), lane)
    module.shoot_periods(*[a.copy() for a in state], drive, 1, np.empty((1, 2, 2)))
    if _compiled_before(module, "lyapunov_periods"):
        module.lyapunov_periods(*[a.copy() for a in state[:2]], np.ones(1), np.zeros(1),
                                *[a.copy() for a in state[2:]], drive, 1.0, np.empty((1, 1)),
                                1, failed.copy(), 0, lane)
    if _compiled_before(module, "shoot_jacobian"):
        module.shoot_jacobian(*[a.copy() for a in state], drive, 1, False,
                              np.empty((1, 2, 3)))
    module.strobe_periods(*[a.copy() for a in state], drive, 1, np.empty((1, 1)),
                          np.empty((1, 1)), np.empty(1), failed.copy(), 0, lane)
    module.acceleration_batch(lane.copy(), lane.copy(), lane.copy())


def _load(key: str, model: ContactModel) -> ModuleType:
    """The kernel module under ``key``, written, compiled and loaded by
    ``perturb.cache.load_generated`` (a damaged file or numba cache: rebuilt once)."""
    return load_generated(usable_cache_dir() / f"kernel_{key}.py", f"_contact_kernel_{key}",
                          lambda: _module_source(model), _smoke)
