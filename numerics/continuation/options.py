"""How a continuation walk steps: its step control and its corrector, one settings object.

``WalkOptions`` holds the tuning of the pseudo-arclength walk that every continuation
takes (``continue_orbits``, ``continue_in_force``, ``switch_branch``, ``fold_curves``).
The defaults are the ones every walk of the toolkit is tested with; the measurements
behind each are in the tuning log, ``docs/tuning.md``. The compiled walk reads the
same numbers as a named tuple of floats (``WalkNumbers``): one source for both engines.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import NamedTuple

from perturb.common import check_int, check_positive

__all__ = ["WalkOptions", "WalkNumbers"]


@dataclass(frozen=True)
class WalkOptions:
    """The tuning of a continuation walk: how its steps grow and shrink, where it takes a
    turn for a corner of the map, and how its Newton corrector stops.

    The largest step, the largest turn between tangents and the most points
    (``ds_max``, ``max_angle``, ``max_points``) are arguments of each walk; these are
    the numbers beneath them. Steps are lengths in the walk's scaled unknowns z (y / y0,
    v / (omega0 y0) and the parameter over its scale). Every field is checked when the
    object is made (a ValueError naming the field).

    Attributes
    ----------
    ds_start : float
        The first step of a walk, and of a walk on after a step in the parameter alone.
    ds_min : float
        Below this step the walk gives up (it has met a corner that Newton cannot pass).
    stall_ds : float
        A step shrunk below this has stalled at a corner where the branch turns back: a
        step in the parameter alone is tried before the step shrinks on to ``ds_min``.
    grow : float
        The next step's factor after an easy step (Newton within ``easy_iterations``).
    shrink : float
        A failed step's factor (above the corner's step).
    easy_iterations : int
        Newton converging within this many iterations makes the step an easy one.
    turn_share : float
        A step whose tangent turns by more than max_angle shrinks by this share of
        max_angle over the turn, by ``shrink`` at least.
    corner_ds : float
        The corner's step on an orbit in contact: a tangent that turns by more than
        max_angle over a shorter step turns at a corner of the piecewise smooth map (a
        switch of the contact within a step), not at a fold, and the step is taken.
    corner_ceiling : float
        On a larger orbit the corner's step grows with the orbit's size, up to this
        factor (and at most ds_max).
    corner_shrink : float
        A failed step below the corner's step shrinks by this, not by ``shrink``.
    straight : float
        Where the tangent turns by at most this [rad] over a step, the branch runs
        straight, and the next step may grow past ds_max with the orbit's size.
    size_reference : float
        The orbit's size |(y, v)| in z beyond which steps grow with it (2: twice the
        static deflection, an orbit that loses contact).
    size_ceiling : float
        Steps on a large straight branch grow up to this factor times ds_max.
    corners : bool
        Take a sharp turn over a step shorter than the corner's step for a corner of
        the map (and let such short steps grow as easy ones do). The fold curves' walk
        takes none: past a corner the fold test jumps.
    shrink_by_turn : bool
        Shrink a step that turned too far by ``turn_share`` of max_angle over the turn
        (by ``shrink`` at least); False: by ``shrink`` alone, as the fold curves' walk.
    near_turn : int
        A fold met by the walk is located when it lies within this many points of a
        significant turn of the parameter; others (turns of a zigzag over the map's
        corners) are only marked.
    newton_tol : float
        Newton stops when the largest component of its update is below this.
    newton_iterations : int
        Newton gives up after this many iterations.
    newton_reach : float
        Newton gives up when an update exceeds this: it has left the point it corrects.
    backtracks : int
        An update that does not reduce |R| is halved, up to this many times.
    contraction : float
        An arclength step's Newton gives up when an update is not at most this share
        of the one before (``math.inf``: no such test).
    stop_by_estimate : bool
        An arclength step's Newton stops once the updates still to come, at the rate
        of the last two, add up to less than ``newton_tol`` (False: by the exact test
        alone).

    Examples
    --------
    >>> WalkOptions().ds_start, WalkOptions(grow=2.0).grow
    (0.001, 2.0)
    >>> WalkOptions(grow=0.5)
    Traceback (most recent call last):
    ...
    ValueError: `grow` must be at least 1, got 0.5.
    >>> WalkOptions.from_dict(WalkOptions(contraction=math.inf).as_dict()).contraction
    inf
    >>> WalkOptions(grow=2, newton_iterations=12.0).as_dict()["newton_iterations"]
    12
    """

    ds_start: float = 1e-3
    ds_min: float = 1e-9
    stall_ds: float = 1e-5  # steps below it took 28 % of R's evaluations at 0.15 Q
    grow: float = 1.5
    shrink: float = 0.5
    easy_iterations: int = 3
    turn_share: float = 0.9  # shrink alone ended the walks at 0.17 Q 7.5 Hz apart, not 5.8
    corner_ds: float = 1e-3  # 1e-4 took a third more points through 0.15 Q's bouncing fold
    corner_ceiling: float = 20.0  # 10 changes the walks at 0.15 Q; 15 to 40 walk them alike
    corner_shrink: float = 0.25  # 9 % fewer evaluations of R than `shrink` at 0.15 Q
    straight: float = 0.03  # 0.01 took 13 % more evaluations for the same App
    size_reference: float = 2.0  # 1 stepped over the 1/3 superharmonic's peak at 0.1 Q
    size_ceiling: float = 20.0  # 40 walks the same at 0.15 Q
    corners: bool = True  # the period map has corners where the contact switches
    shrink_by_turn: bool = True
    near_turn: int = 3  # the report keeps folds within 2 points of a turn; one more kept there
    newton_tol: float = 1e-10  # y to 1e-10 y0; one period's round-off is some 1e-13 y0
    newton_iterations: int = 12
    newton_reach: float = 0.1  # a tenth of y0, of the parameter's scale
    backtracks: int = 6
    contraction: float = 0.5  # failed corrections took 58 % of R's evaluations without it
    stop_by_estimate: bool = True  # saves the evaluation that shows the last update

    def __post_init__(self) -> None:
        for name in ("ds_start", "ds_min", "stall_ds", "corner_ds", "straight",
                     "size_reference", "newton_tol", "newton_reach"):
            check_positive(name, getattr(self, name))
        for name, least in (("grow", 1.0), ("corner_ceiling", 1.0), ("size_ceiling", 1.0)):
            if not getattr(self, name) >= least:
                raise ValueError(f"`{name}` must be at least {least:g}, got "
                                 f"{getattr(self, name)!r}.")
        for name in ("shrink", "turn_share", "corner_shrink"):
            value = getattr(self, name)
            if not 0.0 < value < 1.0:
                raise ValueError(f"`{name}` must lie between 0 and 1, got {value!r}.")
        if not self.contraction > 0.0:
            raise ValueError(f"`contraction` must be positive (inf: no test), got "
                             f"{self.contraction!r}.")
        for name, least in (("easy_iterations", 1), ("near_turn", 0),
                            ("newton_iterations", 1), ("backtracks", 0)):
            check_int(name, getattr(self, name), minimum=least)
        for name in ("stop_by_estimate", "corners", "shrink_by_turn"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(f"`{name}` must be True or False, got "
                                 f"{getattr(self, name)!r}.")
        # Kept as the types the fields name: an integer float would be a float in
        # range(), and an int in a float field a second signature of the compiled walk.
        for field in dataclasses.fields(self):
            kind = {"float": float, "int": int, "bool": bool}[field.type]
            object.__setattr__(self, field.name, kind(getattr(self, field.name)))
        if not self.ds_min <= self.stall_ds <= self.ds_start:
            raise ValueError(f"the steps must keep ds_min <= stall_ds <= ds_start, got "
                             f"{self.ds_min!r}, {self.stall_ds!r} and {self.ds_start!r}.")

    def as_dict(self) -> dict:
        """The fields as a JSON object (``math.inf`` as the string "inf")."""
        return {name: ("inf" if value == math.inf else value)
                for name, value in dataclasses.asdict(self).items()}

    @classmethod
    def from_dict(cls, data: dict) -> WalkOptions:
        """The options that ``as_dict`` wrote (unknown keys are an error naming them)."""
        known = {field.name for field in dataclasses.fields(cls)}
        unknown = sorted(set(data) - known)
        if unknown:
            raise ValueError(f"unknown walk options {unknown}; known: {sorted(known)}.")
        return cls(**{name: (math.inf if value == "inf" else value)
                      for name, value in data.items()})

    def numbers(self, ds_max: float, max_angle: float, f_lo: float,
                f_hi: float) -> WalkNumbers:
        """The numbers of a walk of ``ds_max`` and ``max_angle`` over the band [f_lo, f_hi]
        (in z), as the compiled walk reads them."""
        # Each field of the record is the option of its name, but for the walk's own four.
        given = {"ds_max": ds_max, "max_angle": max_angle, "f_lo": f_lo, "f_hi": f_hi}
        return WalkNumbers(**{name: float(given[name] if name in given else getattr(self, name))
                              for name in WalkNumbers._fields})

    def for_fold_curves(self) -> WalkOptions:
        """The options of a fold curve's walk: the same steps and corrector tolerances,
        but patient Newton (no contraction test, the exact stop), no corners, no stall
        hand-over, no step past ds_max and the plain shrink on a sharp turn. The fold
        system's map has the contact's corners too, but past one the fold test jumps:
        walks that took sharp turns over short steps were measured to crawl there (2000
        points over 1 Hz at 0.065 Q, 1198 Hz)."""
        return dataclasses.replace(self, contraction=math.inf, stop_by_estimate=False,
                                   corners=False, shrink_by_turn=False, stall_ds=self.ds_min,
                                   size_ceiling=1.0)


class WalkNumbers(NamedTuple):
    """``WalkOptions`` as the compiled walk reads them, all floats (numba types a tuple of
    one type as one record), with the walk's own largest step, largest turn and band."""

    ds_min: float
    ds_max: float
    max_angle: float
    grow: float
    shrink: float
    corner_ds: float
    easy_iterations: float
    stall_ds: float
    newton_tol: float
    newton_iterations: float
    newton_reach: float
    backtracks: float
    contraction: float
    stop_by_estimate: float
    f_lo: float
    f_hi: float
    turn_share: float
    straight: float
    size_reference: float
    size_ceiling: float
    corner_ceiling: float
    corner_shrink: float
    corners: float
    shrink_by_turn: float
