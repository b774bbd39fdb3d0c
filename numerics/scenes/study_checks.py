"""What the options of a study cannot check one by one: the checks of the studies of
the continuation studies (continuation, fold curves, the atlas), made when the scene is read.

Each check sees the scene's values (``Checked``), asks the API's own checks where it
has them, and raises ``Invalid`` naming the scene's key; the reader turns that into a
``SceneError`` at the key's line. The API's modules are imported only here, when a
scene of that study is read.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from perturb import ContactParameters

__all__ = ["Checked", "Invalid", "check_atlas", "check_continuation", "check_folds"]


class Invalid(ValueError):
    """A study's check found ``key`` wrong: the reader turns it into a SceneError there."""

    def __init__(self, key: str, message: str) -> None:
        super().__init__(message)
        self.key = key


@dataclass(frozen=True)
class Checked:
    """What a study's check sees: the scene's values, each already checked on its own."""

    options: dict
    pa_frac: tuple[float, ...]
    frequency_hz: np.ndarray
    parameters: ContactParameters
    figures: dict[str, str]


def _api_check(call, *args) -> None:
    """``call(*args)``, a check of the API that names its argument ("`ds_max` must be ..."),
    with its ValueError turned into ``Invalid`` at that option of the [study] table."""
    try:
        call(*args)
    except ValueError as error:
        message = str(error)
        match = re.match(r"`(\w+)` (.*)", message, re.DOTALL)
        name, rest = (match.group(1), match.group(2)) if match else ("", message)
        raise Invalid(f"study.{name}" if name else "study", rest.rstrip(".")) from None


def _check_walk(checked: Checked, period: int) -> None:
    from numerics.continuation.walk import check_walk

    o = checked.options
    _api_check(check_walk, period, o["ds_max"], o["max_angle"], o["max_points"])


def _check_band(checked: Checked, key: str, frequencies) -> None:
    """Each frequency within the band a branch can be continued in, for this model."""
    from numerics.continuation.walk import check_band

    for f in frequencies:
        try:
            check_band("f", float(f), checked.parameters)
        except ValueError as error:
            raise Invalid(key, str(error).removeprefix("`f` ").rstrip(".")) from None


def _check_ends(key: str, values, what: str, positive: bool = False) -> None:
    """``values`` are two, increasing: the ends of a band (the first above 0 if
    ``positive``)."""
    values = [float(v) for v in values]
    if len(values) != 2 or not values[0] < values[1]:
        raise Invalid(key, f"is the {what}: two increasing values [low, high], got {values}")
    if positive and values[0] <= 0:
        raise Invalid(key, f"is the {what}: its low end must be > 0, got {values}")


def check_continuation(checked: Checked) -> None:
    o, pa_frac = checked.options, checked.pa_frac
    if o["continued_in"] == "frequency_hz":
        _check_ends("excitation.frequency_hz", checked.frequency_hz,
                    "band of a continuation in f_e")
        for i, frac in enumerate(pa_frac):
            if frac <= 0:  # at P_a = 0 the orbit is rest at every f_e: nothing to continue
                raise Invalid(f"excitation.pa_frac[{i}]", f"must be > 0 for a continuation in "
                                                          f"f_e, got {frac!r}")
    else:
        _check_ends("excitation.pa_frac", pa_frac, "range of a continuation in P_a")
        if o["switch_branches"]:
            raise Invalid("study.switch_branches", "switches onto the period-doubled branches "
                                                   "of a continuation in f_e, not in pa_frac")
        if "continuation" in checked.figures:
            raise Invalid("output.figures", "the continuation figure draws App against f_e: "
                                            "a continuation in pa_frac has none yet")
    _check_walk(checked, o["period"])
    _check_band(checked, "excitation.frequency_hz", checked.frequency_hz)


def check_folds(checked: Checked) -> None:
    _check_ends("excitation.frequency_hz", checked.frequency_hz, "band of the fold curves in f_e")
    _check_ends("excitation.pa_frac", checked.pa_frac, "band of the fold curves in P_a",
                positive=True)
    seeds, (low, high) = checked.options["seed_pa_fracs"], checked.pa_frac
    if seeds is not None and any(not low <= a <= high for a in seeds):
        raise Invalid("study.seed_pa_fracs", f"must lie within the band of pa_frac "
                                             f"[{low!r}, {high!r}], got {list(seeds)}")
    _check_walk(checked, 1)
    _check_band(checked, "excitation.frequency_hz", checked.frequency_hz)


def check_atlas(checked: Checked) -> None:
    from numerics.steady.census import initial_grid
    from numerics.steady.multistability import MAX_LANES
    from perturb import ContactModel

    o = checked.options
    _check_grid("excitation.frequency_hz", checked.frequency_hz)
    _check_grid("excitation.pa_frac", checked.pa_frac)
    grid = {name: o[name] for name in ("y_over_y0", "v_over_omega0_y0")}
    try:
        states = initial_grid(ContactModel(checked.parameters), grid)[0].size
    except ValueError as error:
        raise Invalid("study.y_over_y0", str(error).rstrip(".")) from None
    lanes = len(checked.frequency_hz) * len(checked.pa_frac) * states
    if lanes > MAX_LANES:
        raise Invalid("excitation", f"asks for {lanes} lanes (cells x {states} initial "
                                    f"states), more than the atlas's limit of {MAX_LANES} "
                                    "(a bound on the work)")
    if o["overlay_folds"]:
        if len(checked.frequency_hz) < 2 or len(checked.pa_frac) < 2 or checked.pa_frac[0] <= 0:
            raise Invalid("study.overlay_folds", "continues fold curves over the atlas's box: "
                                                 "it needs two frequencies or more and two "
                                                 "amplitudes or more, the least above 0")
        _check_band(checked, "excitation.frequency_hz", checked.frequency_hz)


def _check_grid(key: str, values) -> None:
    """``values`` are one value or evenly spaced and increasing: an axis of the atlas."""
    values = np.asarray(values, dtype=float)
    if values.size < 2:
        return
    even = np.linspace(values[0], values[-1], values.size)
    # A list written by hand (0.05, 0.1, 0.15) differs from linspace by round-off only.
    if not values[0] < values[-1] or np.max(np.abs(values - even)) > 1e-9 * (even[-1] - even[0]):
        raise Invalid(key, f"is an axis of the atlas's grid: evenly spaced and increasing (a "
                           f"range {{start, stop, count}}), got {values.tolist()}")
