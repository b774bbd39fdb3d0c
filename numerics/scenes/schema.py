"""A scene file: one study written as data (TOML, read with ``tomllib``, never evaluated).

Every key is checked here against the tables below, and every error is one
``SceneError`` that names the file, the key, its line where it can be found, and
the value. No string of a scene reaches ``eval``, ``exec``, ``sympify`` or
``lambdify``: names are looked up in fixed tables, numbers are TOML numbers.
"""

from __future__ import annotations

import importlib
import math
import re
import tomllib
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from perturb import EQ_2_6, FULL, LINEAR, ContactParameters, Effects, parameters_with
from perturb.series.truncation import TRUNCATIONS

from .study_checks import Checked, Invalid, check_atlas, check_continuation, check_folds

__all__ = ["Scene", "SceneError", "read_scene", "parse_scene", "STUDIES", "OBSERVABLES",
           "NAMED_EFFECTS", "Study", "Option"]

#: What each observable is (the scene's ``observables`` list names them).
OBSERVABLES = {
    "app": "peak-to-peak amplitude A_pp of the steady response",
    "extrema": "every local maximum and minimum of y over the response period",
    "time_history": "y and v after every RK4 step",
    "spectrum": "amplitudes of the harmonics of one response period",
    "phase_portrait": "v against y over the response period",
    "hysteresis": "the contact pressure against y over one period (Fig. 5)",
    "contact_fraction": "fraction of each period spent out of contact (y <= 0)",
}

#: Effects by name: ``effects = "full"`` and so on, or a table of ``Effects`` fields.
NAMED_EFFECTS = {"full": FULL, "eq26": EQ_2_6, "linear": LINEAR}


@dataclass(frozen=True)
class ApiDefault:
    """A default that the module running the study owns (``module.table[key]``), read
    only when a scene of that study is checked: the schema imports no study's module."""

    module: str
    table: str
    key: str

    def value(self):
        return getattr(importlib.import_module(self.module), self.table)[self.key]


@dataclass(frozen=True)
class Option:
    """One key of a [study] table: its kind, default and range (``None`` as the default:
    the API's own choice, which TOML cannot write)."""

    kind: str  # "int", "float", "bool", "choice", "steps", "ints", "floats"
    default: object
    minimum: float | None = None
    maximum: float | None = None
    choices: tuple = ()
    strict_minimum: bool = False  # the value must be above ``minimum``, not equal to it


def _steps(default="auto") -> Option:
    return Option("steps", default, 4, 2**16)


@dataclass(frozen=True)
class Study:
    """A kind of study: its options, the observables it can give, its default figures."""

    options: dict[str, Option]
    observables: tuple[str, ...]
    default_observables: tuple[str, ...]
    figures: tuple[str, ...]
    needs: tuple[str, ...] = ()  # excitation keys it needs: "pa_frac", "frequency_hz"
    auto: bool = False  # whether effects = "auto" applies
    #: Checks what the options' own ranges cannot (``check(checked) -> None``, ``checked``
    #: a ``Checked``); it raises ``Invalid`` naming the scene's key (``study_checks``).
    check: Callable | None = None


# --- the continuation studies: continuation, fold curves, the atlas --------------------------

def _walk_options(module: str) -> dict[str, Option]:
    """The step control of a pseudo-arclength walk, with ``module``'s defaults."""
    def default(key):
        return ApiDefault(module, "DEFAULTS", key)

    return {"steps_per_period": _steps(default("steps_per_period")),
            "ds_max": Option("float", default("ds_max"), 0, strict_minimum=True),
            "max_angle": Option("float", default("max_angle"), 0, strict_minimum=True),
            "max_points": Option("int", default("max_points"), 2)}


_STEADY = ("app", "extrema", "spectrum", "contact_fraction")
#: Which terms of the contact's equation a series keeps (``perturb.derive``).
_TRUNCATION = Option("choice", "consistent", choices=TRUNCATIONS)
#: Figures drawn from an observable, which the scene must ask for (a sweep's App figure
#: is drawn from the sweep itself).
_FIGURE_NEEDS = {name: name for name in ("app", "spectrum", "contact_fraction",
                                         "phase_portrait", "time_history")}
#: The studies a scene can run, by ``[study] kind``.
STUDIES: dict[str, Study] = {
    "sweep": Study(
        {"direction": Option("choice", "both", choices=("up", "down", "both")),
         "steps_per_period": _steps()},
        _STEADY, ("app", "extrema"), ("app", "extrema", "spectrum", "contact_fraction"),
        needs=("pa_frac", "frequency_hz"), auto=True),
    "attractors": Study(
        {"steps_per_period": _steps()},
        _STEADY + ("phase_portrait",), ("app",), ("census", "phase_portrait", "spectrum"),
        needs=("pa_frac", "frequency_hz"), auto=True),
    "time_history": Study(
        {"periods": Option("int", 200, 1, 10**6), "record_periods": Option("int", 4, 1, 10**4),
         "steps_per_period": Option("int", 256, 4, 2**16)},
        _STEADY + ("time_history", "phase_portrait", "hysteresis"),
        ("time_history", "app"), ("time_history", "phase_portrait", "spectrum"),
        needs=("pa_frac", "frequency_hz"), auto=True),
    "hysteresis": Study(
        {"periods": Option("int", 400, 1, 10**6), "steps_per_period": Option("int", 512, 4, 2**16)},
        ("hysteresis", "app"), ("hysteresis",), ("hysteresis",),
        needs=("pa_frac", "frequency_hz")),
    "analytic_response": Study(
        {"order": Option("int", 6, 0, 20), "truncation": _TRUNCATION},
        ("app", "extrema"), ("app",), ("app",),
        needs=("pa_frac", "frequency_hz")),
    "backbone": Study(
        {"order": Option("int", 8, 1, 40), "points": Option("int", 200, 2, 10**5),
         "truncation": _TRUNCATION},
        ("app",), ("app",), ("backbone",)),
    "derivation": Study({"order": Option("int", 4, 0, 12), "truncation": _TRUNCATION},
                        (), (), ()),
    "natural_frequency": Study({"points": Option("int", 100, 2, 10**5)}, (), (),
                               ("natural_frequency",)),
    "comparison": Study(
        {"orders": Option("ints", (2, 4, 6, 8), 0, 20),
         "steps_per_period": Option("int", 128, 4, 2**16), "truncation": _TRUNCATION},
        ("app",), ("app",), ("comparison",), needs=("pa_frac", "frequency_hz")),
    "continuation": Study(
        {"continued_in": Option("choice", "frequency_hz", choices=("frequency_hz", "pa_frac")),
         "period": Option("int", 1, 1), **_walk_options("numerics.continuation.walk"),
         "switch_branches": Option("bool", False)},
        (), (), ("continuation",), needs=("pa_frac", "frequency_hz"),
        check=check_continuation),
    "folds": Study(
        {"seed_pa_fracs": Option("floats", None, 0, strict_minimum=True),
         **_walk_options("numerics.continuation.folds")},
        (), (), ("folds",), needs=("pa_frac", "frequency_hz"), check=check_folds),
    "atlas": Study(
        {"workers": Option("int", None, 1),
         "steps_per_period": _steps(ApiDefault("numerics.steady.shooting", "DEFAULTS",
                                               "steps_per_period")),
         "tol": Option("float", ApiDefault("numerics.steady.shooting", "DEFAULTS", "tol"), 0, 0.5,
                       strict_minimum=True),
         "y_over_y0": Option("floats", ApiDefault("numerics.steady.census", "DEFAULT_GRID",
                                                  "y_over_y0")),
         "v_over_omega0_y0": Option("floats", ApiDefault("numerics.steady.census", "DEFAULT_GRID",
                                                         "v_over_omega0_y0")),
         "overlay_folds": Option("bool", False)},
        (), (), ("atlas",), needs=("pa_frac", "frequency_hz"), check=check_atlas),
}

#: Studies whose effects are fixed: the series is of Eq. 2.6, the comparison runs both.
_DEFAULT_EFFECTS = {"analytic_response": "eq26", "derivation": "eq26", "comparison": "full",
                    "natural_frequency": "eq26"}
_FIXED_WHY = {"analytic_response": "solves the series of Eq. 2.6 (truncation = \"paper\")",
              "derivation": "derives the series of Eq. 2.6 (truncation = \"paper\")",
              "natural_frequency": "is f_n0 of Eq. 2.6 in closed form",
              "comparison": "compares the series with RK4 of Eq. 2.6 and of the full model"}

#: The studies of one series, whose effects follow its truncation.
_SERIES_KINDS = ("analytic_response", "derivation")
_CONSISTENT_WHY = ("solves the consistent series of the contact's own equation in contact; "
                   "truncation = \"paper\" solves Eq. 2.6's on effects \"eq26\"")


def _fixed_effects(kind: str, options: dict) -> str | None:
    """The effects a study fixes: the analytic response's follow its truncation (Eq. 2.6's
    series: "eq26"; the consistent series of the contact's own laws: "full")."""
    if kind in _SERIES_KINDS and options.get("truncation") == "consistent":
        return "full"
    return _DEFAULT_EFFECTS.get(kind)


_TOP = ("title", "description", "effects", "observables", "tolerance", "model", "excitation",
        "study", "output", "unchecked")
_EXCITATION = ("pa_frac", "frequency_hz")
_RANGE = ("start", "stop", "count")
_OUTPUT = ("json", "figures", "animation", "text")
_ANIMATION = ("kind", "frames", "fps", "frequency_hz")
#: The most frequencies one scene may list or count.
MAX_FREQUENCIES = 100_000
DEFAULT_TOLERANCE = 5e-3


class SceneError(ValueError):
    """A scene file that cannot be run: the file, the key (and line), the value."""

    def __init__(self, source: str, key: str, message: str, line: int | None = None) -> None:
        where = f"{source}:{line}" if line else source
        super().__init__(f"{where}: `{key}` {message}" if key else f"{where}: {message}")
        self.source, self.key, self.line = source, key, line


@dataclass(frozen=True)
class Scene:
    """A checked scene: everything a run needs, with every default filled in."""

    source: str
    title: str
    description: str
    parameters: ContactParameters
    effects: Effects | None  # None: "auto"
    pa_frac: tuple[float, ...]
    frequency_hz: np.ndarray
    study: str
    options: dict
    observables: tuple[str, ...]
    tolerance: float
    figures: dict[str, str]  # figure kind -> file name
    json: str | None
    text: str | None
    animation: dict | None
    overrides: dict = field(default_factory=dict)
    #: Past the ranges where the answers are measured to hold (``numerics.simulation.ranges``).
    unchecked: bool = False

    @property
    def auto(self) -> bool:
        return self.effects is None

    def as_dict(self) -> dict:
        """The scene as checked, defaults filled in (the ``settings`` of its result)."""
        return {"source": self.source, "title": self.title, "model_overrides": self.overrides,
                "effects": "auto" if self.auto else self.effects.__dict__.copy(),
                "pa_frac": list(self.pa_frac), "frequency_hz": self.frequency_hz.tolist(),
                "study": self.study, "options": self.options,
                "observables": list(self.observables), "tolerance": self.tolerance,
                "figures": self.figures, "json": self.json, "text": self.text,
                "animation": self.animation, "unchecked": self.unchecked}


def read_scene(path: str | Path) -> Scene:
    """Read and check a scene file; a SceneError names what is wrong, and where."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise SceneError(str(path), "", f"cannot be read: {error}") from None
    return parse_scene(text, str(path))


def parse_scene(text: str, source: str = "<scene>") -> Scene:
    """Check the TOML ``text`` of a scene (``source`` names it in errors)."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        line = _decode_line(error)
        raise SceneError(source, "", f"is not valid TOML: {error}", line) from None
    except RecursionError:
        raise SceneError(source, "", "nests its tables or arrays too deep to read") from None
    return _Reader(text, source).scene(data)


def _decode_line(error: tomllib.TOMLDecodeError) -> int | None:
    match = re.search(r"line (\d+)", str(error))
    return int(match.group(1)) if match else None


class _Reader:
    """Checks one scene's data, key by key, and knows where each key was written."""

    def __init__(self, text: str, source: str) -> None:
        self.lines = text.splitlines()
        self.source = source

    def line_of(self, key: str) -> int | None:
        """The line where ``key`` ("table.name") is set, found by a plain scan."""
        table, _, name = key.rpartition(".")
        table = table.split("[")[0]
        current = ""
        for number, line in enumerate(self.lines, 1):
            stripped = line.strip()
            header = re.fullmatch(r"\[\s*([A-Za-z0-9_.]+)\s*\]", stripped)
            if header:
                current = header.group(1)
                if current == key:
                    return number
                continue
            if current == table and re.match(rf"{re.escape(name.split('[')[0])}\s*=", stripped):
                return number
            if not table and current == "" and re.match(rf"{re.escape(name)}\s*=", stripped):
                return number
        return None

    def fail(self, key: str, message: str):
        raise SceneError(self.source, key, message, self.line_of(key))

    def mapping(self, key: str, value, allowed) -> dict:
        if not isinstance(value, dict):
            self.fail(key, f"must be a table, got {value!r}")
        for name in value:
            if name not in allowed:
                self.fail(f"{key}.{name}" if key else name,
                          f"is not a key of a scene{f' [{key}]' if key else ''}; the keys are "
                          f"{', '.join(allowed)}")
        return value

    def number(self, key: str, value, *, minimum=None, maximum=None, integer=False,
               strict_minimum=False):
        kind = int if integer else (int, float)
        if isinstance(value, bool) or not isinstance(value, kind):
            self.fail(key, f"must be {'an integer' if integer else 'a number'}, got {value!r}")
        if not math.isfinite(value):
            self.fail(key, f"must be finite, got {value!r}")
        if minimum is not None and (value <= minimum if strict_minimum else value < minimum):
            self.fail(key, f"must be {'>' if strict_minimum else '>='} {minimum}, got {value!r}")
        if maximum is not None and value > maximum:
            self.fail(key, f"must be <= {maximum}, got {value!r}")
        return value if integer else float(value)

    def string(self, key: str, value, choices=None) -> str:
        if not isinstance(value, str):
            self.fail(key, f"must be a string, got {value!r}")
        if choices is not None and value not in choices:
            self.fail(key, f"must be one of {', '.join(map(str, choices))}; got {value!r}")
        return value

    def file_name(self, key: str, value) -> str:
        """A plain file name, written into the output folder (never a path elsewhere)."""
        name = self.string(key, value)
        if not re.fullmatch(r"[A-Za-z0-9_.\-]+", name) or name.startswith("."):
            self.fail(key, f"must be a plain file name (letters, digits, '_', '-', '.'; "
                           f"written into the output folder), got {value!r}")
        return name

    # --- the tables -----------------------------------------------------------------------

    def scene(self, data: dict) -> Scene:
        self.mapping("", data, _TOP)
        if "study" not in data:
            self.fail("study", f"is missing: a scene names its study, one of "
                               f"{', '.join(STUDIES)}")
        study_table = data["study"]
        if not isinstance(study_table, dict) or "kind" not in study_table:
            self.fail("study.kind", f"is missing: one of {', '.join(STUDIES)}")
        kind = self.string("study.kind", study_table["kind"], tuple(STUDIES))
        study = STUDIES[kind]
        options = self.options(kind, study, study_table)
        overrides = self.model(data.get("model", {}))
        parameters = self.parameters(overrides)
        if (kind in _SERIES_KINDS and data.get("effects") == "eq26"
                and "truncation" not in study_table):
            options = {**options, "truncation": "paper"}  # Eq. 2.6's model: its series
        fixed = _fixed_effects(kind, options)
        effects = self.effects(data.get("effects", fixed or "full"), study, kind, fixed)
        pa_frac, frequency = self.excitation(data.get("excitation"), study, kind)
        observables = self.observables(data.get("observables"), study, kind)
        tolerance = self.number("tolerance", data.get("tolerance", DEFAULT_TOLERANCE),
                                minimum=0, maximum=0.5, strict_minimum=True)
        output = self.mapping("output", data.get("output", {}), _OUTPUT)
        figures = self.figures(output.get("figures", []), study, kind, observables)
        if study.check is not None:
            try:
                study.check(Checked(options, pa_frac, frequency, parameters, figures))
            except Invalid as error:
                self.fail(error.key, str(error))
        return Scene(
            source=self.source,
            title=self.string("title", data.get("title", Path(self.source).stem)),
            description=self.string("description", data.get("description", "")),
            parameters=parameters, effects=effects, pa_frac=pa_frac, frequency_hz=frequency,
            study=kind, options=options, observables=observables, tolerance=tolerance,
            figures=figures,
            json=self.file_name("output.json", output["json"]) if "json" in output else None,
            text=self.file_name("output.text", output["text"]) if "text" in output else None,
            animation=self.animation(output.get("animation"), kind),
            overrides=overrides,
            unchecked=self.option("unchecked", data.get("unchecked", False),
                                  Option("bool", False)),
        )

    def options(self, kind: str, study: Study, table: dict) -> dict:
        options = {}
        for name in table:
            if name != "kind" and name not in study.options:
                self.fail(f"study.{name}", f"is not an option of a {kind} study; its options "
                                           f"are {', '.join(study.options) or 'none'}")
        for name, option in study.options.items():
            key, value = f"study.{name}", table.get(name, option.default)
            if isinstance(value, ApiDefault):
                value = value.value()
            options[name] = None if value is None else self.option(key, value, option)
        return options

    def option(self, key: str, value, option: Option):
        if option.kind == "choice":
            return self.string(key, value, option.choices)
        if option.kind == "bool":
            if not isinstance(value, bool):
                self.fail(key, f"must be true or false, got {value!r}")
            return value
        if option.kind == "steps" and value == "auto":
            return value
        if option.kind in ("ints", "floats"):
            integer = option.kind == "ints"
            if not isinstance(value, (list, tuple)) or not value:
                self.fail(key, f"must be a non-empty list of "
                               f"{'integers' if integer else 'numbers'}, got {value!r}")
            return tuple(self.number(f"{key}[{i}]", v, minimum=option.minimum,
                                     maximum=option.maximum, integer=integer,
                                     strict_minimum=option.strict_minimum)
                         for i, v in enumerate(value))
        if option.kind == "steps" and not isinstance(value, int):
            self.fail(key, f"must be \"auto\" or an integer >= {option.minimum}, got {value!r}")
        return self.number(key, value, minimum=option.minimum, maximum=option.maximum,
                           integer=option.kind in ("int", "steps"),
                           strict_minimum=option.strict_minimum)

    def model(self, table) -> dict:
        self.mapping("model", table, ContactParameters.names())
        return {name: self.number(f"model.{name}", value) for name, value in table.items()}

    def parameters(self, overrides: dict) -> ContactParameters:
        try:
            return parameters_with(overrides)
        except ValueError as error:
            message, name = str(error).rstrip(".") + ".", ""
            name = next((n for n in overrides if message.startswith(f"`{n}` ")), "")
            if name:  # the key is named once, in front: "`model.M` must be > 0"
                message = message.removeprefix(f"`{name}` ")
            self.fail(f"model.{name}" if name else "model", message)

    def effects(self, value, study: Study, kind: str, fixed: str | None) -> Effects | None:
        if fixed is not None and value != fixed:
            why = _FIXED_WHY[kind] if fixed == _DEFAULT_EFFECTS[kind] else _CONSISTENT_WHY
            self.fail("effects", f"of a {kind} study are {fixed!r} (it {why}); got {value!r}")
        if value == "auto":
            if not study.auto:
                self.fail("effects", f"= \"auto\" applies to the studies "
                                     f"{', '.join(k for k, s in STUDIES.items() if s.auto)}, "
                                     f"not to {kind}")
            return None
        if isinstance(value, str):
            self.string("effects", value, tuple(NAMED_EFFECTS) + ("auto",))
            return NAMED_EFFECTS[value]
        table = self.mapping("effects", value, Effects.names())
        try:
            return Effects(**table)
        except ValueError as error:
            name = next((n for n in table if f"`{n}`" in str(error)), "")
            self.fail(f"effects.{name}" if name else "effects", str(error))

    def excitation(self, table, study: Study, kind: str) -> tuple[tuple, np.ndarray]:
        if table is None:
            if study.needs:
                self.fail("excitation", f"is missing: a {kind} study needs "
                                        f"{' and '.join(study.needs)}")
            return (), np.empty(0)
        self.mapping("excitation", table, _EXCITATION)
        for name in study.needs:
            if name not in table:
                self.fail(f"excitation.{name}", f"is missing: a {kind} study needs it")
        fracs = table.get("pa_frac", [])
        if isinstance(fracs, dict):
            fracs = self.range("excitation.pa_frac", fracs, positive=False).tolist()
        fracs = fracs if isinstance(fracs, list) else [fracs]
        if "pa_frac" in study.needs and not fracs:
            self.fail("excitation.pa_frac", "must name at least one amplitude, got []")
        pa_frac = tuple(self.number(f"excitation.pa_frac[{i}]", f, minimum=0)
                        for i, f in enumerate(fracs))
        if len(set(pa_frac)) != len(pa_frac):
            self.fail("excitation.pa_frac", f"must not repeat an amplitude, got {list(pa_frac)}")
        return pa_frac, self.frequencies(table.get("frequency_hz", []))

    def range(self, key: str, value: dict, positive: bool = True) -> np.ndarray:
        """``count`` values evenly from ``start`` to ``stop`` (both > 0 if ``positive``,
        else >= 0)."""
        self.mapping(key, value, _RANGE)
        for name in _RANGE:
            if name not in value:
                self.fail(f"{key}.{name}", "is missing: a range has start, stop and count")
        start = self.number(f"{key}.start", value["start"], minimum=0, strict_minimum=positive)
        stop = self.number(f"{key}.stop", value["stop"], minimum=0, strict_minimum=positive)
        count = self.number(f"{key}.count", value["count"], minimum=1,
                            maximum=MAX_FREQUENCIES, integer=True)
        if count > 1 and not start < stop:
            self.fail(f"{key}.stop", f"must be above start={start:g}, got {stop!r}")
        return np.linspace(start, stop, count)

    def frequencies(self, value) -> np.ndarray:
        key = "excitation.frequency_hz"
        if isinstance(value, dict):
            return self.range(key, value)
        values = value if isinstance(value, list) else [value]
        if not values:
            self.fail(key, "must name at least one frequency, got []")
        if len(values) > MAX_FREQUENCIES:
            self.fail(key, f"lists {len(values)} frequencies, more than {MAX_FREQUENCIES}")
        grid = np.array([self.number(f"{key}[{i}]", f, minimum=0, strict_minimum=True)
                         for i, f in enumerate(values)], dtype=float)
        if grid.size > 1 and np.any(np.diff(grid) <= 0):
            self.fail(key, f"must be strictly increasing, got {values!r}")
        return grid

    def observables(self, value, study: Study, kind: str) -> tuple[str, ...]:
        if value is None:
            return study.default_observables
        if not isinstance(value, list) or not value:
            self.fail("observables", f"must be a non-empty list of names, got {value!r}")
        for i, name in enumerate(value):
            self.string(f"observables[{i}]", name, tuple(OBSERVABLES))
            if name not in study.observables:
                gives = ", ".join(study.observables) or "none"
                self.fail("observables", f"a {kind} study gives {gives}; got {name!r}")
        return tuple(dict.fromkeys(value))

    def figures(self, value, study: Study, kind: str, observables) -> dict[str, str]:
        if isinstance(value, list):
            names = {self.string(f"output.figures[{i}]", v, study.figures): f"{v}.png"
                     for i, v in enumerate(value)}
            figures = {k: v.replace("_", "-") for k, v in names.items()}
        else:
            table = self.mapping("output.figures", value, study.figures)
            figures = {name: self.file_name(f"output.figures.{name}", file)
                       for name, file in table.items()}
        for figure in figures:
            need = _FIGURE_NEEDS.get(figure)
            if need and need not in observables and not (figure == "app" and kind == "sweep"):
                self.fail("output.figures", f"the {figure} figure draws the observable "
                                            f"{need!r}: add it to `observables`")
        return figures

    def animation(self, value, kind: str) -> dict | None:
        if value is None or value is False:
            return None
        if kind not in ("sweep",):
            self.fail("output.animation", f"is drawn from a sweep scene, not from a {kind} study")
        table = {} if value is True else self.mapping("output.animation", value, _ANIMATION)
        animation = {"kind": self.string("output.animation.kind", table.get("kind", "sweep"),
                                         ("sweep", "slider")),
                     "frames": self.number("output.animation.frames", table.get("frames", 60),
                                           minimum=2, maximum=2000, integer=True),
                     "fps": self.number("output.animation.fps", table.get("fps", 20),
                                        minimum=1, maximum=100, integer=True)}
        if "frequency_hz" in table:
            animation["frequency_hz"] = self.number("output.animation.frequency_hz",
                                                    table["frequency_hz"], minimum=0,
                                                    strict_minimum=True)
        return animation


