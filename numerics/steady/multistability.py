"""Multistability atlas: the attractor census over a grid of (f_e, P_a).

Section 3.3 of the paper describes its bi- and multi-stable regions in words; the
atlas maps them: at every cell of a grid of f_e and P_a, the number of distinct
attractors the census finds from its initial states, their periods and labels, and
the fraction of lanes that never settle.

The cells are independent. They are cut into tasks of consecutive cells (row by row
of P_a), each task one batch of ``censuses``, so that the compiled kernel advances a
few thousand lanes per call, and the tasks go to a ``concurrent.futures.Executor``:
a local process pool by default, or any other (``Client.get_executor()`` of
dask.distributed spreads them over a cluster). How the cells are cut depends on the
input alone, never on the executor or its workers. A lane's result does not depend on
the batch it runs in (each lane iterates Newton until it converges itself), so the
atlas is bit-identical however it is run, and would stay so if that changed.

A task that raises is reported, with its message, as failed cells; the others
complete.
"""

from __future__ import annotations

import multiprocessing
import sys
import time
from collections import Counter
from concurrent.futures import Executor, Future, ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool

import numpy as np

from perturb import ContactModel, eq26_numbers
from perturb.common import (
    Result,
    Status,
    check_int,
    check_positive,
    note,
    processors,
    progress,
    result,
    tied_to_this_process,
)

from ..kernels.codegen import compiled_kernels
from ..simulation.ranges import check_tested
from ..simulation.rk4 import check_model
from .census import (
    LYAPUNOV_PERIODS,
    Census,
    census_settings,
    censuses,
    check_lyapunov_periods,
    initial_grid,
)
from .options import SteadyOptions, steady_options
from .shooting import DEFAULTS, lane_steps

__all__ = ["Atlas", "atlas", "MAX_LANES", "TASK_LANES", "TASK_SAMPLES"]

#: The most lanes (cells x initial states) of one atlas: a bound on the work, refused
#: before any is done. At the rate make bench measures (100 x 50 cells x 50 initial
#: states in 16.8 s with 2 workers: 67 us per lane) this is some 2 to 3 minutes.
MAX_LANES = 2_000_000
#: The time per lane (cell x initial state) that the estimate of ``atlas`` takes, in
#: seconds: the rate above, with 2 worker processes.
LANE_SECONDS = 67e-6
#: A task holds consecutive cells up to about this many lanes: enough that the kernel's
#: calls, not Python, take the time (bench_atlas.py: time per cell against cells per task)...
TASK_LANES = 2048
#: ... and up to this many lane-steps per period (lanes x steps per period), since
#: every lane keeps its orbit, y at every step: 8 MiB a period at most, for a task.
TASK_SAMPLES = 2048 * 512
#: How many times the tasks of a local pool that broke (a worker died) are run again.
RETRIES = 2


@result
class Atlas(Result):
    """The attractor census at every cell of a grid of (f_e, P_a).

    Arrays over cells have the shape (P_a, f_e): row ``i`` is ``pa_frac[i]``, column
    ``j`` is ``frequency_hz[j]``; the per-attractor lists are nested the same way,
    each cell's list largest basin first.

    Attributes
    ----------
    frequency_hz : ndarray, shape (NF,)
    pa_frac : ndarray, shape (NP,)
    attractor_count : ndarray of int, shape (NP, NF)
        Distinct attractors at the cell (-1 where the cell's task failed).
    attractor_periods, attractor_labels, attractor_basins, attractor_app_m : list
        Per cell, per attractor: period p, label, basin fraction, App [m].
    not_settled_fraction : ndarray, shape (NP, NF)
        Fraction of the cell's lanes that did not settle (NaN where the task failed).
    chaotic_fraction : ndarray, shape (NP, NF)
        Fraction of the cell's lanes that are chaotic: their largest Lyapunov exponent
        is positive beyond its error (NaN where the task failed or it was not measured).
    status : ndarray of int, shape (NP, NF)
        ``Status.SUCCESS``, or ``Status.FAILED`` where the cell's task raised.
    message : list of list of str
        The task's error where it failed ("" elsewhere).
    """

    frequency_hz: np.ndarray
    pa_frac: np.ndarray
    attractor_count: np.ndarray
    attractor_periods: list[list[list[int]]]
    attractor_labels: list[list[list[str]]]
    attractor_basins: list[list[list[float]]]
    attractor_app_m: list[list[list[float]]]
    not_settled_fraction: np.ndarray
    chaotic_fraction: np.ndarray
    status: np.ndarray
    message: list[list[str]]
    model: dict
    settings: dict
    elapsed_s: float

    @property
    def cell_time_s(self) -> float:
        """Wall time per cell [s] (what a larger grid or a cluster can be estimated by)."""
        return self.elapsed_s / self.status.size

    def derived(self) -> dict:
        return {"cell_time_s": self.cell_time_s}

    def csv_rows(self) -> list[dict]:
        """A row a cell (P_a, then f_e): the count, shares and status, and each
        attractor's label, period, basin and App, joined by ";"."""
        rows = []
        for i, pa_frac in enumerate(self.pa_frac):
            for j, frequency_hz in enumerate(self.frequency_hz):
                rows.append({
                    "pa_frac": pa_frac, "frequency_hz": frequency_hz,
                    "attractor_count": self.attractor_count[i, j],
                    "not_settled_fraction": self.not_settled_fraction[i, j],
                    "chaotic_fraction": self.chaotic_fraction[i, j],
                    "status": self.status[i, j], "message": self.message[i][j],
                    **{name: ";".join(str(v) for v in getattr(self, name)[i][j])
                       for name in ("attractor_labels", "attractor_periods",
                                    "attractor_basins", "attractor_app_m")}})
        return rows

    def summary(self) -> str:
        failed = int((self.status == Status.FAILED).sum())
        most = int(self.attractor_count.max(initial=-1))
        retried = self.settings.get("tasks_retried", 0)
        return (f"Atlas of {self.pa_frac.size} x {self.frequency_hz.size} cells (P_a x f_e), "
                f"up to {most} coexisting attractors"
                + (f", {failed} cells failed" if failed else "")
                + (f", {retried} tasks run again after a worker was lost" if retried else "")
                + f" ({self.elapsed_s:.3g} s, {self.cell_time_s * 1e3:.3g} ms per cell)")

    def table(self) -> str:
        """How many cells hold each number of attractors; the failed tasks' messages."""
        counts = Counter(self.attractor_count[self.status == Status.SUCCESS].tolist())
        lines = [f"  {k} attractor{'s' if k != 1 else ''}: {n} cells"
                 for k, n in sorted(counts.items())]
        errors = Counter(m for row in self.message for m in row if m)
        lines += [f"  failed ({n} cells): {m}" for m, n in errors.items()]
        return "\n".join(lines)


#: What the atlas keeps of one census, field by field: one line per per-cell field
#: (a further per-lane observable, such as the largest Lyapunov exponent of the lanes
#: that never settle, is one more line here and one more field of ``Atlas``).
_CELL_FIELDS = {
    "attractor_count": lambda c: len(c.attractors),
    "attractor_periods": lambda c: [a.period for a in c.attractors],
    "attractor_labels": lambda c: [a.label for a in c.attractors],
    "attractor_basins": lambda c: [a.basin_fraction for a in c.attractors],
    "attractor_app_m": lambda c: [a.app_m for a in c.attractors],
    "not_settled_fraction": lambda c: c.not_settled_fraction,
    "chaotic_fraction": lambda c: c.chaotic_fraction,
}
#: The fields of a cell whose task failed.
_FAILED_CELL = {"attractor_count": -1, "attractor_periods": [], "attractor_labels": [],
                "attractor_basins": [], "attractor_app_m": [], "not_settled_fraction": np.nan,
                "chaotic_fraction": np.nan}
_ARRAY_FIELDS = {"attractor_count": np.int64, "not_settled_fraction": float,
                 "chaotic_fraction": float}


def atlas(
    fmin_hz: float,
    fmax_hz: float,
    pa_min: float,
    pa_max: float,
    grid: tuple[int, int] = (20, 10),
    *,
    executor: Executor | None = None,
    workers: int | None = None,
    initial_states: dict | None = None,
    model: ContactModel | None = None,
    steps_per_period: int | str = DEFAULTS["steps_per_period"],
    tol: float = DEFAULTS["tol"],
    max_periods: int | None = DEFAULTS["max_periods"],
    lyapunov_periods: int | None = LYAPUNOV_PERIODS,
    quiet: bool = True,
    unchecked: bool = False,
    options: SteadyOptions | None = None,
    task_lanes: int = TASK_LANES,
) -> Atlas:
    """The attractor census at every cell of a grid of (f_e, P_a).

    Parameters
    ----------
    fmin_hz, fmax_hz : float
        The band of f_e [Hz]; ``grid[0]`` frequencies, ends included (equal ends with
        one frequency).
    pa_min, pa_max : float
        The range of P_a / Q; ``grid[1]`` amplitudes, ends included.
    grid : (int, int)
        (NF, NP): frequencies and amplitudes. At most ``MAX_LANES`` lanes in all
        (cells x initial states).
    executor : concurrent.futures.Executor, optional
        Runs the tasks, e.g. ``dask.distributed.Client(...).get_executor()``. By
        default a pool of worker processes on this machine (kept while the atlas runs).
    workers : int, optional
        The default pool's processes (all the processors this process may use by
        default; 1 runs the tasks in this process). Not with ``executor``.
    initial_states : dict, optional
        The census's initial states, as ``attractors``' ``grid`` (``DEFAULT_GRID``).
    model, steps_per_period, tol, max_periods, lyapunov_periods, options
        As in ``attractor_census``.
    quiet : bool
        No progress bar (over the tasks) on stderr.
    unchecked : bool
        Go past the ranges of f_e, P_a and the contact where the answers are measured
        to hold (``numerics.simulation.ranges.TESTED``); refused otherwise.
    task_lanes : int
        About how many lanes (cells x initial states) a task holds: fewer make more,
        smaller tasks, to spread over more workers. The results are the same, bit for
        bit, however the grid is cut.

    Returns
    -------
    Atlas
        Per cell, the attractors' count, periods, labels, basins and App, and the
        fraction of lanes not settled; failed tasks' cells have ``Status.FAILED`` and
        the task's message.

    Examples
    --------
    >>> found = atlas(480.0, 500.0, 0.5, 0.5, grid=(2, 1), workers=1)
    >>> found.attractor_count.tolist(), found.attractor_periods[0][0]
    ([[4, 4]], [1, 1, 1, 2])
    """
    model = check_model(model)
    f_axis, pa_axis = check_axes(fmin_hz, fmax_hz, pa_min, pa_max, grid)
    sizes = f_axis[2], pa_axis[2]
    states = _states(model, initial_states)
    lanes = sizes[0] * sizes[1] * states
    if lanes > MAX_LANES:  # refused before the axes are allocated
        raise ValueError(f"`grid` {sizes} with {states} initial states asks for "
                         f"{lanes} lanes, more than the limit of {MAX_LANES} (some 2 to 3 "
                         "minutes on 2 processors): split the grid or take fewer initial "
                         "states.")
    frequencies, amplitudes = np.linspace(*f_axis), np.linspace(*pa_axis)
    check_tested(frequencies[[0, -1]], amplitudes[[0, -1]], model, unchecked=unchecked)
    options = steady_options(options, steps_per_period=steps_per_period, tol=tol,
                             max_periods=max_periods)
    check_lyapunov_periods(lyapunov_periods)
    accuracy = {"options": options, "lyapunov_periods": lyapunov_periods}
    executor, workers = _check_executor(executor, workers)
    start = time.perf_counter()
    f_cells, pa_cells = (a.ravel() for a in np.meshgrid(frequencies, amplitudes))
    rate = eq26_numbers(model.parameters).fastest_rate_per_s
    tasks = task_cells(lane_steps(options.steps_per_period, f_cells, rate), states,
                       check_int("task_lanes", task_lanes))
    jobs = [(_run_task, f_cells[t], pa_cells[t], model, initial_states, accuracy) for t in tasks]
    note(f"atlas: {sizes[0]} x {sizes[1]} cells x {states} initial states = {lanes} lanes in "
         f"{len(jobs)} tasks; some {lanes * LANE_SECONDS:.2g} s at the rate of 2 local "
         "workers", quiet=quiet)
    outcomes, retried = _run(jobs, executor, workers, model, quiet)
    cells_found = [cell for task, outcome in zip(tasks, outcomes)
                   for cell in _cells_of(task, outcome)]
    settings = census_settings(initial_states, states, options, lyapunov_periods)
    settings |= {"cells": [frequencies.size, amplitudes.size], "tasks": len(tasks),
                 "tasks_retried": retried, **({"unchecked": True} if unchecked else {})}
    return Atlas(frequency_hz=frequencies, pa_frac=amplitudes, model=model.as_dict(),
                 settings=settings, elapsed_s=time.perf_counter() - start,
                 **_assemble(cells_found, amplitudes.size, frequencies.size))


def task_cells(steps: np.ndarray, states: int, task_lanes: int = TASK_LANES
               ) -> list[np.ndarray]:
    """Consecutive cells, grouped into tasks of about ``task_lanes`` lanes, or TASK_SAMPLES
    lane-steps if that is fewer. ``steps``: each cell's steps per period.

    The cut depends on the cells alone (see the module's docstring): each cell's load
    is its share of a task, and a task ends with the cell whose load reaches the next
    whole unit of the running total (so it exceeds its share by less than one cell;
    a cell larger than a task is a task alone).
    """
    load = np.maximum(states / task_lanes, states * steps / TASK_SAMPLES)
    task = np.floor(np.cumsum(load) - load).astype(np.int64)
    return np.split(np.arange(steps.size), np.flatnonzero(np.diff(task)) + 1)


def _run_task(frequency_hz, pa_frac, model, grid, accuracy) -> list[dict]:
    """One task, in a worker: the census of its cells in one batch, each reduced to
    what the atlas keeps."""
    return [_cell(census) for census in censuses(frequency_hz, pa_frac, model=model, grid=grid,
                                                 **accuracy)]


def _cell(census: Census) -> dict:
    return {name: keep(census) for name, keep in _CELL_FIELDS.items()}


def _cells_of(task: np.ndarray, outcome: list[dict] | str) -> list[tuple[int, dict, str]]:
    """(cell, its fields, message) for each cell of a task: the task's error if it failed."""
    if isinstance(outcome, str):
        return [(int(cell), _FAILED_CELL, outcome) for cell in task]
    return [(int(cell), fields, "") for cell, fields in zip(task, outcome)]


def _assemble(cells: list[tuple[int, dict, str]], rows: int, columns: int) -> dict:
    """The Atlas's per-cell fields, (P_a, f_e)-shaped, from the cells in any order."""
    cells = sorted(cells, key=lambda cell: cell[0])
    out = {}
    for name in _CELL_FIELDS:
        values = [fields[name] for _, fields, _ in cells]
        if name in _ARRAY_FIELDS:
            out[name] = np.array(values, dtype=_ARRAY_FIELDS[name]).reshape(rows, columns)
        else:
            out[name] = _rows(values, columns)
    out["status"] = np.array([Status.FAILED if m else Status.SUCCESS for _, _, m in cells],
                             dtype=np.int64).reshape(rows, columns)
    out["message"] = _rows([m for _, _, m in cells], columns)
    return out


def _rows(values: list, columns: int) -> list[list]:
    return [values[i : i + columns] for i in range(0, len(values), columns)]


def _run(jobs: list[tuple], executor: Executor | None, workers: int, model: ContactModel,
         quiet: bool) -> tuple[list[list[dict] | str], int]:
    """Each job's result, or its error as "Type: message", in the jobs' order; and how
    many tasks were run again.

    In the local pool, a task whose worker process died (killed, out of memory: the
    pool breaks, and every task still in it fails with ``BrokenProcessPool``) is
    submitted again on a fresh pool, up to ``RETRIES`` times; a task that raised an
    error of its own is not. (dask resubmits a lost worker's tasks itself.)
    """
    own = executor is None
    if own:
        compiled_kernels(model)  # loaded (or built) once here: forked workers inherit it
        if workers == 1:
            return _run_here(jobs, quiet), 0
    outcomes: list = [None] * len(jobs)
    pending, retried = list(range(len(jobs))), set()
    bar = progress(len(jobs), "atlas tasks", quiet=quiet)
    for attempt in range(RETRIES + 1 if own else 1):
        pool = _local_pool(min(workers, len(pending))) if own else executor
        lost = _submit(pool, [jobs[k] for k in pending], pending, outcomes, bar, own)
        if not lost:
            break
        if attempt == RETRIES:  # lost for good: reported as failed, with the pool's message
            bar.update(len(lost))
            break
        retried.update(lost)
        pending = lost
    bar.close()
    return outcomes, len(retried)


def _submit(pool: Executor, jobs: list[tuple], index: list[int], outcomes: list, bar,
            own: bool) -> list[int]:
    """Run ``jobs`` on ``pool``, each outcome into ``outcomes[index[k]]``; the indices of
    the tasks lost with a broken local pool (their outcome says so, should they not be
    run again)."""
    futures: dict[Future, int] = {}
    lost = []
    try:
        for k, job in zip(index, jobs):
            try:
                futures[pool.submit(*job)] = k
            except BrokenProcessPool as error:  # broke while tasks were still submitted
                if not own:
                    raise
                outcomes[k] = _message(error)
                lost.append(k)
        for future in as_completed(futures):
            k = futures[future]
            outcomes[k] = _outcome(future)
            if own and isinstance(future.exception(), BrokenProcessPool):
                lost.append(k)
            else:
                bar.update()
    except BaseException:  # Ctrl-C included: no task left running for nothing
        for future in futures:
            future.cancel()
        if own:
            pool.shutdown(wait=False, cancel_futures=True)
        raise
    if own:
        pool.shutdown()
    return sorted(lost)


def _run_here(jobs: list[tuple], quiet: bool) -> list[list[dict] | str]:
    """``_run`` in this process, one task after the other."""
    outcomes = []
    bar = progress(len(jobs), "atlas tasks", quiet=quiet)
    for function, *args in jobs:
        try:
            outcomes.append(function(*args))
        except Exception as error:  # reported as the task's failure, as a pool would
            outcomes.append(_message(error))
        bar.update()
    bar.close()
    return outcomes


def _outcome(future: Future) -> list[dict] | str:
    error = future.exception()
    return future.result() if error is None else _message(error)


def _message(error: BaseException) -> str:
    return f"{type(error).__name__}: {error}"


def _local_pool(workers: int) -> Executor:
    """Worker processes on this machine: forked on Linux (they start at once, with the
    kernels this process loaded), spawned elsewhere."""
    method = "fork" if sys.platform.startswith("linux") else None
    return ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context(method),
                               initializer=tied_to_this_process())


def _check_executor(executor, workers) -> tuple[Executor | None, int]:
    if executor is not None:
        if not isinstance(executor, Executor):
            raise ValueError("`executor` must be a concurrent.futures.Executor (for dask: "
                             f"Client.get_executor()), got {executor!r}.")
        if workers is not None:
            raise ValueError("`workers` sizes the default pool: give `executor` or "
                             f"`workers`, not both (got workers={workers!r}).")
        return executor, 0
    if workers is None:
        return None, processors()
    # Each worker is a process that holds the model's kernels; past the processors
    # they only wait their turn.
    return None, check_int("workers", workers, maximum=2 * processors(),
                           why=f"twice the {processors()} processors this process may use")


def _grid_size(grid, axis: int) -> int:
    try:
        sizes = tuple(grid)
    except TypeError:
        sizes = ()
    if len(sizes) != 2:
        raise ValueError(f"`grid` must be two integers (frequencies, amplitudes), got {grid!r}.")
    return check_int(f"grid[{axis}]", sizes[axis], minimum=1)


def check_axes(fmin_hz, fmax_hz, pa_min, pa_max, grid) -> tuple[tuple, tuple]:
    """The two axes of the atlas, checked, as (low, high, points) each: the ends in order,
    or equal with one point on the axis. A ValueError names the argument (the command
    line tells it as its option); nothing is allocated yet."""
    return (_axis("fmin_hz", fmin_hz, "fmax_hz", fmax_hz, _grid_size(grid, 0), True),
            _axis("pa_min", pa_min, "pa_max", pa_max, _grid_size(grid, 1), False))


def _axis(low_name: str, low, high_name: str, high, points: int, positive: bool) -> tuple:
    low = check_positive(low_name, low, allow_zero=not positive)
    high = check_positive(high_name, high, allow_zero=not positive)
    if points == 1 and low != high:
        raise ValueError(f"`{high_name}` must equal `{low_name}` with one point on its axis of "
                         f"`grid`, got {low!r} and {high!r}.")
    if points > 1 and not low < high:
        raise ValueError(f"`{high_name}` must be above `{low_name}`, got {low!r} and {high!r}.")
    return low, high, points


def _states(model: ContactModel, initial_states: dict | None) -> int:
    """How many initial states each cell starts from, or a ValueError naming them."""
    try:
        return initial_grid(model, initial_states)[0].size
    except ValueError as error:
        raise ValueError(f"`initial_states`: {error}") from None
