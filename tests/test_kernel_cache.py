"""The cache on disk: a broken file is rebuilt, an unwritable folder is replaced, and
the cached numbers of Eq. 2.6 are the ones sympy derives.

Regression (issue 10): a truncated or empty cached kernel file used to give a
SyntaxError or AttributeError in every later run, a garbled numba cache an
UnpicklingError in every later run, and an unwritable cache folder a traceback.
The tests of the source file skip the first calls of the kernels (which compile
them); the test of numba's cache compiles the linear model's kernels twice.

Issue 12: the numbers of Eq. 2.6 are cached too (``perturb.model.numbers``), so that a
warm command never imports sympy; they must be exactly what sympy derives, for the
paper's model and another one, and a damaged numbers file is derived again.
"""

import errno
import json
import os
import sys
import warnings

import pytest

from numerics.kernels import codegen
from perturb import EQ_2_6, LINEAR, PAPER, ContactModel, eq26_numbers, parameters_with
from perturb import cache as cache_module
from perturb.cache import _writable
from perturb.model import eq26
from perturb.model import numbers as numbers_module

from .test_cli_info import closed_forms

MODEL = ContactModel(effects=LINEAR)
#: A rough contact unlike the paper's: fractional exponents of both laws.
OTHER = parameters_with({"m2": 1.5, "l": 0.5})


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("CONTACT_RESONANCES_CACHE", str(tmp_path))
    return tmp_path / "kernels"


@pytest.fixture
def no_first_calls(monkeypatch):
    monkeypatch.setattr(codegen, "_smoke", lambda module: None)


def _path(cache):
    return cache / f"kernel_{codegen._cache_key(MODEL)}.py"


@pytest.mark.parametrize("damage", ["truncated", "emptied", "edited"])
def test_a_damaged_kernel_file_is_rebuilt(cache, damage, no_first_calls):
    key = codegen._cache_key(MODEL)
    codegen._load(key, MODEL)
    path = _path(cache)
    text = path.read_text()
    broken = {"truncated": text[: len(text) // 2], "emptied": "",
              "edited": text.replace("def advance_periods", "def advance_period")}[damage]
    path.write_text(broken)
    module = codegen._load(key, MODEL)
    assert cache_module.intact(path) and path.read_text() == text
    assert callable(module.advance_periods)


def test_an_intact_file_that_does_not_import_is_rebuilt(cache, no_first_calls):
    key = codegen._cache_key(MODEL)
    path = _path(cache)
    path.parent.mkdir(parents=True)
    body = "raise ImportError('a broken cache beside the file')\n"
    cache_module.write_generated(path, body)
    assert cache_module.intact(path)
    module = codegen._load(key, MODEL)
    assert callable(module.record_periods) and cache_module.intact(path)


def test_an_unwritable_cache_folder_falls_back_with_one_warning(monkeypatch):
    monkeypatch.setenv("CONTACT_RESONANCES_CACHE", "/proc/contact-resonances")
    monkeypatch.setattr(cache_module, "_WARNED", set())  # the warning comes once per process
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        folder = codegen.usable_cache_dir()
    assert [w.category for w in caught] == [codegen.CacheWarning]
    assert "not writable" in str(caught[0].message)
    assert _writable(folder) and not str(folder).startswith("/proc")


def test_the_fallback_folder_is_not_one_that_another_user_can_write(monkeypatch, tmp_path):
    # A review found the fallback at a predictable path in /tmp, used as found: another
    # user could create it first and plant files that this one would import. A folder
    # others may write is passed over for a new one of this process's own.
    monkeypatch.setattr(cache_module.tempfile, "tempdir", str(tmp_path))
    monkeypatch.setattr(cache_module, "_PRIVATE", [])
    shared = tmp_path / f"contact-resonances-{os.getuid()}"
    assert cache_module._private_temporary_folder() == shared  # made here: this user's own
    assert shared.stat().st_mode & 0o777 == 0o700
    shared.chmod(0o775)  # as an older release made it under umask 002: others may write
    with pytest.warns(cache_module.CacheWarning, match="can be written by others"):
        other = cache_module._private_temporary_folder()
    assert other != shared and other.parent == tmp_path and other.stat().st_mode & 0o077 == 0
    assert cache_module._private_temporary_folder() == other  # one per process, removed at exit


def test_a_garbled_numba_cache_is_rebuilt(cache):
    # numba loads the machine code at a kernel's first call, not at import: the first
    # calls made while loading find the garbled files, and the module is rebuilt.
    key = codegen._cache_key(MODEL)
    codegen._load(key, MODEL)
    numba_files = list(cache.glob("__pycache__/*.nb*"))
    assert numba_files
    for path in numba_files:
        path.write_bytes(b"garbage")
    module = codegen._load(key, MODEL)
    assert callable(module.advance_periods)
    assert all(p.read_bytes() != b"garbage" for p in cache.glob("__pycache__/*.nb*"))


def test_the_lyapunov_kernel_compiles_at_its_first_call_only(cache, monkeypatch):
    # Loading compiles EAGER_KERNELS; the Lyapunov kernel (some 1 s of a model's 7.7 s)
    # compiles when first called, and from then on loading checks its cache too.
    key = codegen._cache_key(MODEL)
    assert not codegen.kernels_built(MODEL)
    module = codegen._load(key, MODEL)
    assert codegen.kernels_built(MODEL)
    assert not codegen._compiled_before(module, "lyapunov_periods")
    assert not list(cache.glob("__pycache__/*.lyapunov_periods-*"))
    with monkeypatch.context() as patched:
        patched.setattr(codegen, "_compiled_before", lambda module, name: True)
        codegen._smoke(module)  # its first call
    assert codegen._compiled_before(module, "lyapunov_periods")


@pytest.fixture
def fresh_numbers(cache):
    """An empty cache and no numbers remembered by this process."""
    numbers_module._numbers.cache_clear()
    yield cache
    numbers_module._numbers.cache_clear()


def _derived_again(parameters):
    raise AssertionError(f"derived again for {parameters!r}, not read from the cache")


@pytest.mark.parametrize("parameters", [PAPER, OTHER], ids=["paper", "m2=1.5,l=0.5"])
def test_cached_numbers_are_the_sympy_derivation(parameters, fresh_numbers, monkeypatch):
    derived = eq26.derive_numbers(parameters)  # sympy, no cache
    first = eq26_numbers(parameters)  # derived and written
    assert numbers_module.numbers_path(parameters).exists()
    numbers_module._numbers.cache_clear()
    monkeypatch.setattr(eq26, "derive_numbers", _derived_again)
    read = eq26_numbers(parameters)
    # JSON writes a float's shortest repr, which reads back to the same float: exact.
    assert read == first == derived
    # And against the closed forms typed by hand (rounding of a few float operations).
    by_hand = closed_forms(**dict(zip(("S", "C_N", "M2", "H_N", "L", "M", "G"),
                                      parameters.as_dict().values())))
    for key, value in read.as_dict().items():
        assert value == pytest.approx(by_hand[key], rel=1e-13), key


def test_numbers_are_keyed_by_the_parameters_and_kernels_by_the_effects_too(fresh_numbers):
    # Eq. 2.6's numbers do not depend on the effects (one file serves every reduced
    # model of a parameter set); the kernels do.
    assert numbers_module.numbers_path(PAPER) != numbers_module.numbers_path(OTHER)
    keys = {codegen._cache_key(ContactModel(PAPER, effects)) for effects in (LINEAR, EQ_2_6)}
    assert len(keys) == 2


@pytest.mark.parametrize("damage", ["truncated", "emptied", "other parameters", "not finite",
                                    "one digit of y0 edited"])
def test_a_damaged_numbers_file_is_derived_again(damage, fresh_numbers):
    expected = eq26_numbers(OTHER)
    path = numbers_module.numbers_path(OTHER)
    text = path.read_text()
    record = json.loads(text)
    if damage == "other parameters":
        record["parameters"]["M"] *= 2
    if damage == "not finite":
        record["numbers"]["y0_m"] = None
    if damage == "one digit of y0 edited":  # a finite float, for these parameters: only
        digits = repr(record["numbers"]["y0_m"])  # the checksum tells
        record["numbers"]["y0_m"] = float(digits[:3] + str((int(digits[3]) + 1) % 10)
                                          + digits[4:])
        assert record["numbers"]["y0_m"] != expected.y0_m
    broken = {"truncated": text[: len(text) // 2], "emptied": ""}.get(damage, json.dumps(record))
    path.write_text(broken)
    numbers_module._numbers.cache_clear()
    assert eq26_numbers(OTHER) == expected
    assert json.loads(path.read_text()) == json.loads(text)  # written again


def test_numbers_in_an_unwritable_cache_folder(monkeypatch):
    monkeypatch.setenv("CONTACT_RESONANCES_CACHE", "/proc/contact-resonances-numbers")
    monkeypatch.setattr(cache_module, "_WARNED", set())
    numbers_module._numbers.cache_clear()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        numbers = eq26_numbers(OTHER)
    numbers_module._numbers.cache_clear()
    assert [w.category for w in caught] == [codegen.CacheWarning]
    assert numbers == eq26.derive_numbers(OTHER)


# -- load_generated: the one loader of the generated modules (kernels, walk, series) and
# write_atomically's temporary file. These use a tiny module without numba: its "machine
# code" is a file in __pycache__ named as numba names its cache files.

_GENERATED = "VALUE = 7\n\n\ndef value():\n    return VALUE\n"


class _Source:
    """The generated text, counting how often it is asked for (each time: written)."""

    def __init__(self) -> None:
        self.calls = 0

    def __call__(self) -> str:
        self.calls += 1
        return _GENERATED


def _smoke_ok(module) -> None:
    assert module.value() == 7


@pytest.fixture
def generated(tmp_path, monkeypatch):
    """The path of a generated module, its numba-like cache file, and the module's name
    (forgotten by sys.modules after the test)."""
    name = "_contact_test_generated"
    monkeypatch.delitem(sys.modules, name, raising=False)
    yield tmp_path / "gen_0123.py", tmp_path / "__pycache__" / "gen_0123.value-4.py312.nbi", name
    sys.modules.pop(name, None)


def _machine_code(cached) -> None:
    cached.parent.mkdir(exist_ok=True)
    cached.write_bytes(b"compiled")


def test_a_missing_module_is_written_once_and_then_only_loaded(generated):
    path, _, name = generated
    source = _Source()
    assert cache_module.load_generated(path, name, source, _smoke_ok).value() == 7
    assert cache_module.intact(path) and source.calls == 1
    assert cache_module.load_generated(path, name, source, _smoke_ok).value() == 7
    assert source.calls == 1  # found intact: not written again


@pytest.mark.parametrize("damage", ["truncated", "emptied", "edited"])
def test_a_damaged_module_is_written_again_and_its_machine_code_removed(generated, damage):
    path, cached, name = generated
    source = _Source()
    cache_module.load_generated(path, name, source, _smoke_ok)
    _machine_code(cached)
    text = path.read_text()
    path.write_text({"truncated": text[: len(text) // 2], "emptied": "",
                     "edited": text.replace("VALUE = 7", "VALUE = 8")}[damage])
    assert not cache_module.intact(path)
    assert cache_module.load_generated(path, name, source, _smoke_ok).value() == 7
    assert source.calls == 2 and path.read_text() == text and not cached.exists()


def test_a_module_whose_smoke_call_fails_is_rebuilt_once(generated):
    # An intact file beside garbled machine code fails only when called (numba loads its
    # cache at the first call): removed with its machine code, written, loaded again.
    path, cached, name = generated
    source = _Source()
    cache_module.write_generated(path, _GENERATED)
    _machine_code(cached)
    calls = []

    def smoke(module):
        calls.append(cached.exists())
        if cached.exists():
            raise RuntimeError("garbled machine code")

    assert cache_module.load_generated(path, name, source, smoke).value() == 7
    assert calls == [True, False] and source.calls == 1 and cache_module.intact(path)


def test_a_module_that_fails_again_after_its_rebuild_raises(generated):
    path, _, name = generated
    source = _Source()

    def smoke(module):
        raise RuntimeError("always")

    with pytest.raises(RuntimeError, match="always"):
        cache_module.load_generated(path, name, source, smoke)
    assert source.calls == 2 and name not in sys.modules


def test_a_failed_write_leaves_no_temporary_file(tmp_path, monkeypatch):
    # Regression: write_atomically left its .tmpPID file behind when the write failed
    # (a full disk); the file it replaces is left as it was.
    path = tmp_path / "numbers_0123.json"
    path.write_text("old")
    with pytest.raises(UnicodeEncodeError):  # opened, then the text cannot be encoded
        cache_module.write_atomically(path, "a lone surrogate \ud800")
    assert [p.name for p in tmp_path.iterdir()] == [path.name] and path.read_text() == "old"

    def full_disk(self, text, *args, **kwargs):
        with open(self, "w") as file:
            file.write(text[:3])
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(type(path), "write_text", full_disk)
    with pytest.raises(OSError, match="No space"):
        cache_module.write_atomically(path, "new text")
    assert [p.name for p in tmp_path.iterdir()] == [path.name] and path.read_text() == "old"


def test_a_comment_or_docstring_edit_keeps_every_key_and_a_code_edit_changes_it(
        monkeypatch, tmp_path):
    # The kernels' and the series' keys hash the code of their sources, not their text:
    # editing a comment, a docstring or the layout of any of them rebuilds nothing; a
    # change of one constant rebuilds.
    copies = {}
    for path in codegen.KERNEL_SOURCES:
        copy = tmp_path / path.parent.name / path.name
        copy.parent.mkdir(exist_ok=True)
        copy.write_text(path.read_text())
        copies[path] = copy
    sources = tuple(copies.values())
    before = cache_module.cache_key("values", sources)
    template = copies[codegen._TEMPLATE]
    text = template.read_text()
    edited = text.replace('"""The batched RK4 kernels, as a template.',
                          '"""The batched RK4 kernels, as a template (edited).', 1)
    edited = edited.replace("import math\n", "import math  # a comment\n\n", 1)
    assert edited.count("(edited)") == 1 and "# a comment" in edited
    template.write_text(edited)
    assert cache_module.cache_key("values", sources) == before
    template.write_text(edited.replace("MAX_SWITCHES = 16", "MAX_SWITCHES = 17", 1))
    assert cache_module.cache_key("values", sources) != before
