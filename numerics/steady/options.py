"""How steady states are found and trusted: one settings object for both routes.

``SteadyOptions`` holds the accuracy a caller chooses (the step, the tolerances, the
settling cap, the refinements) and the steady-state engine's own decisions (how far
Newton may move a guess, how the approach of a continued orbit is checked, when an
error estimate is trusted). ``steady_states``, ``sweep``, ``attractor_census`` and
``atlas`` take it as ``options=``, or its accuracy fields as keywords.

The Python route reads every field. The compiled sweep takes the accuracy fields at run
time and is built with the default engine decisions frozen into its machine code; a
sweep whose engine fields differ from the defaults takes the Python route
(``SteadyOptions.engine_is_default``). The measurements behind the defaults are in the
tuning log, ``docs/tuning.md``, and beside the fields below.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from perturb.common import check_choice, check_int, check_positive

__all__ = ["SteadyOptions", "ACCURACY_FIELDS", "steady_options"]

#: The fields a caller chooses per call (``steady_states``' keywords); the others are the
#: engine's decisions.
ACCURACY_FIELDS = ("steps_per_period", "tol", "app_rtol", "max_periods", "method",
                   "refinements")
#: The most steps per period any pass takes, refinements included (a drive table of
#: 2^21 + 1 numbers; a period of one lane then takes a few milliseconds).
MAX_STEPS = 2**20
#: The longest period an orbit is sought with (``shooting.PERIODS_TRIED``): the approach
#: check marches at least one whole orbit of it.
LONGEST_PERIOD = 8
_MAX_REFINEMENTS = 8


@dataclass(frozen=True)
class SteadyOptions:
    """How steady states are found, and when one is trusted.

    Every field is checked when the object is made (a ValueError naming the field).
    The defaults give App to 0.5 % on the paper's model (tests/test_steady.py shows it).

    Attributes
    ----------
    steps_per_period : int or "auto"
        RK4 steps per excitation period; "auto" follows f_e: at least 128, and a power
        of two large enough that rate * dt <= 0.5, the rate being the contact's fastest
        (omega0 or its overdamped decay), up to 2^16.
    tol : float
        Relative tolerance of the stroboscopic repeat, and of Newton's orbit.
    app_rtol : float or None
        Bound on App's estimated relative error from the step. A settled lane above it
        is solved again with more steps (``refinements``) and, if still above, is
        under-resolved. None: no estimate is made.
    max_periods : int or None
        Cap of time marching per lane, in periods. None: 30 decay times 1/c of the
        linearised contact, within 1,200 and 120,000 periods.
    method : {"newton", "march"}
        Newton shooting with time marching as the fallback, or time marching only (the
        paper's method; for checks and baselines).
    refinements : int
        Lanes that fail, do not settle, settle with p > 1 or too coarsely are solved
        again with 2, 4, ... times the steps, this many times.
    newton_iterations : int
        Newton shooting gives up after this many iterations.
    reach_continuation : float
        How far Newton may move a sweep's guess, relative to the orbit's App: further,
        it has left the orbit it was started on.
    reach_polish : float
        How far Newton may move a marched, settled state (or a coarse orbit refined).
    distinct_lag : float
        A p-periodic orbit is taken only where the lag-q stroboscopic differences of
        every divisor q of p exceed this many ``tol``: when lag p first repeats within
        tol on the way to a q-periodic orbit, lag q is about |1 - mu| tol <= 2 tol.
    verify_periods : int
        The march that confirms that a continued orbit attracts the previous state, in
        periods (at least 8, the longest period sought: a whole orbit) ...
    verify_shrink : float
        ... and by how much the distance to that orbit must shrink meanwhile.
    verify_first : int
        A lane whose march followed the orbit's linearisation for its first this many
        periods is decided then, by the linearisation's prediction of the distance at
        ``verify_periods`` (``verify_periods``: every lane marches the whole check).
    verify_linear : float
        The march follows the linearisation where it stays within this share of the
        first distance from it.
    early_shrink : float
        An early lane is accepted where the predicted distance is below this share of
        the one-stage criterion, ``verify_shrink``.
    sharpen_slack : float
        How far App may move when an orbit is refined at twice the steps, in units of
        its coarse step-error estimate.
    unestimated_slack : float
        ... and, where the coarse step was too coarse to estimate, this share of App.
    resolved_omega_dt : float
        The error estimate is trusted where omega * dt at the orbit's stiffest point is
        at most this (above, it is inf: the lane is refined or under-resolved).
    unknown_amplification : float
        The orbit's sensitivity 1 / (1 - |mu|) where its multipliers are not known (a
        lane settled by marching alone).
    order_factor : float
        2^q - 1 for the step-error estimate's order q (q = 2: RK4 through a kink).

    Examples
    --------
    >>> SteadyOptions().tol, SteadyOptions(steps_per_period=256).steps_per_period
    (1e-06, 256)
    >>> SteadyOptions(tol=-1.0)
    Traceback (most recent call last):
    ...
    ValueError: `tol` must be > 0, got -1.0.
    >>> SteadyOptions.from_dict(SteadyOptions(verify_first=16).as_dict()).verify_first
    16
    >>> SteadyOptions(verify_first=16).engine_is_default()
    False
    """

    steps_per_period: int | str = "auto"
    tol: float = 1e-6
    app_rtol: float | None = 5e-3
    max_periods: int | None = None
    method: str = "newton"
    refinements: int = 2
    newton_iterations: int = 10
    reach_continuation: float = 0.5
    reach_polish: float = 1e-2
    distinct_lag: float = 10.0
    verify_periods: int = 16
    verify_shrink: float = 0.5
    verify_first: int = 4  # 11,075 checks agreed with the one-stage check (tuning log)
    verify_linear: float = 0.02  # departing lanes deviated by 0.099 at least (tuning log)
    early_shrink: float = 0.7  # the prediction's error was 0.095 of the first distance at most
    sharpen_slack: float = 2.0  # App(2N) - App(N) is at most about the error at N
    unestimated_slack: float = 1e-2  # such orbits moved 1.8e-3 at most on the Fig. 2 + 3 job
    resolved_omega_dt: float = 0.5  # above 0.75 the estimate passed wrong states
    unknown_amplification: float = 10.0  # |mu| = 0.9, about the paper's primary peak
    order_factor: float = 3.0  # q = 2, RK4's order through the kink of loss of contact

    def __post_init__(self) -> None:
        check_choice("method", self.method, ("newton", "march"))
        set_ = lambda name, value: object.__setattr__(self, name, value)  # noqa: E731
        set_("refinements", check_int("refinements", self.refinements, minimum=0,
                                      maximum=_MAX_REFINEMENTS, why="each doubles the steps"))
        check_steps(self.steps_per_period, self.refinements)
        if self.steps_per_period != "auto":
            set_("steps_per_period", int(self.steps_per_period))
        set_("tol", check_positive("tol", self.tol))
        if self.app_rtol is not None:
            set_("app_rtol", check_positive("app_rtol", self.app_rtol))
        if self.max_periods is not None:
            set_("max_periods", check_int("max_periods", self.max_periods))
        for name in ("newton_iterations", "verify_first"):
            set_(name, check_int(name, getattr(self, name), minimum=1))
        set_("verify_periods", check_int("verify_periods", self.verify_periods,
                                         minimum=LONGEST_PERIOD))
        if self.verify_first > self.verify_periods:
            raise ValueError(f"`verify_first` must be at most `verify_periods` "
                             f"({self.verify_periods}), got {self.verify_first}.")
        for name in ("reach_continuation", "reach_polish", "distinct_lag", "sharpen_slack",
                     "unestimated_slack", "resolved_omega_dt", "unknown_amplification",
                     "order_factor"):
            set_(name, check_positive(name, getattr(self, name)))
        for name in ("verify_shrink", "verify_linear", "early_shrink"):
            value = getattr(self, name)
            if not 0.0 < value <= 1.0:
                raise ValueError(f"`{name}` must lie in (0, 1], got {value!r}.")
            set_(name, float(value))

    def accuracy(self) -> dict:
        """The accuracy fields, as a result's ``settings`` records them."""
        return {name: getattr(self, name) for name in ACCURACY_FIELDS}

    def engine_is_default(self) -> bool:
        """Whether the engine's decisions are the defaults (the compiled sweep's)."""
        default = SteadyOptions()
        return all(getattr(self, f.name) == getattr(default, f.name)
                   for f in dataclasses.fields(self) if f.name not in ACCURACY_FIELDS)

    def engine_changes(self) -> dict:
        """The engine's decisions that differ from the defaults, by name."""
        default = SteadyOptions()
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)
                if f.name not in ACCURACY_FIELDS
                and getattr(self, f.name) != getattr(default, f.name)}

    def replace(self, **changes) -> SteadyOptions:
        """These options with ``changes`` (checked again)."""
        return dataclasses.replace(self, **changes)

    def as_dict(self) -> dict:
        """The fields as a JSON object."""
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, data: dict) -> SteadyOptions:
        """The options that ``as_dict`` wrote (unknown keys are an error naming them)."""
        known = {field.name for field in dataclasses.fields(cls)}
        unknown = sorted(set(data) - known)
        if unknown:
            raise ValueError(f"unknown steady-state options {unknown}; known: {sorted(known)}.")
        return cls(**data)


def steady_options(options: SteadyOptions | None, **accuracy) -> SteadyOptions:
    """The options of a call that takes ``options=`` and the accuracy fields as keywords:
    ``options`` when no keyword is moved from its default, or the keywords' own options.
    A keyword moved from its default beside ``options`` is refused, naming it (which
    would win is not clear); one left at its default defers to ``options``."""
    if options is None:
        return SteadyOptions(**accuracy)
    if not isinstance(options, SteadyOptions):
        raise TypeError(f"`options` must be a SteadyOptions, got {type(options).__name__}.")
    moved = [name for name, value in accuracy.items() if value != getattr(SteadyOptions, name)]
    if moved:
        raise ValueError(f"`{moved[0]}` given beside `options`; set it in the options "
                         f"(options.replace({moved[0]}=...)).")
    return options


def check_steps(steps_per_period, refinements: int = 0) -> None:
    """``"auto"`` or an integer >= 4 whose refinements stay within MAX_STEPS, or a
    ValueError naming the argument."""
    if steps_per_period != "auto":
        check_int("steps_per_period", steps_per_period, minimum=4,
                  maximum=MAX_STEPS // 2**refinements,
                  why=f"with {refinements} refinement(s) doubling it, at most {MAX_STEPS}")
