"""The kernel cache on disk: a broken file is rebuilt, an unwritable folder is replaced.

Regression (issue 10): a truncated or empty cached kernel file used to give a
SyntaxError or AttributeError in every later run, a garbled numba cache an
UnpicklingError in every later run, and an unwritable cache folder a traceback.
The tests of the source file skip the first calls of the kernels (which compile
them); the test of numba's cache compiles the linear model's kernels twice.
"""

import warnings

import pytest

from numerics import _codegen
from perturb import LINEAR, ContactModel

MODEL = ContactModel(effects=LINEAR)


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("CONTACT_RESONANCES_CACHE", str(tmp_path))
    return tmp_path / "kernels"


@pytest.fixture
def no_first_calls(monkeypatch):
    monkeypatch.setattr(_codegen, "_smoke", lambda module: None)


def _path(cache):
    return cache / f"kernel_{_codegen._cache_key(MODEL)}.py"


@pytest.mark.parametrize("damage", ["truncated", "emptied", "edited"])
def test_a_damaged_kernel_file_is_rebuilt(cache, damage, no_first_calls):
    key = _codegen._cache_key(MODEL)
    _codegen._load(key, MODEL)
    path = _path(cache)
    text = path.read_text()
    broken = {"truncated": text[: len(text) // 2], "emptied": "",
              "edited": text.replace("def advance_periods", "def advance_period")}[damage]
    path.write_text(broken)
    module = _codegen._load(key, MODEL)
    assert _codegen._intact(path) and path.read_text() == text
    assert callable(module.advance_periods)


def test_an_intact_file_that_does_not_import_is_rebuilt(cache, no_first_calls):
    key = _codegen._cache_key(MODEL)
    path = _path(cache)
    path.parent.mkdir(parents=True)
    body = "raise ImportError('a broken cache beside the file')\n"
    path.write_text(f"{_codegen._checksum(body)}\n{body}")
    module = _codegen._load(key, MODEL)
    assert callable(module.record_periods) and _codegen._intact(path)


def test_an_unwritable_cache_folder_falls_back_with_one_warning(monkeypatch):
    monkeypatch.setenv("CONTACT_RESONANCES_CACHE", "/proc/contact-resonances")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        folder = _codegen.usable_cache_dir()
    assert [w.category for w in caught] == [_codegen.CacheWarning]
    assert "not writable" in str(caught[0].message)
    assert _codegen._writable(folder) and not str(folder).startswith("/proc")


def test_a_garbled_numba_cache_is_rebuilt(cache):
    # numba loads the machine code at a kernel's first call, not at import: the first
    # calls made while loading find the garbled files, and the module is rebuilt.
    key = _codegen._cache_key(MODEL)
    _codegen._load(key, MODEL)
    numba_files = list(cache.glob("__pycache__/*.nb*"))
    assert numba_files
    for path in numba_files:
        path.write_bytes(b"garbage")
    module = _codegen._load(key, MODEL)
    assert callable(module.advance_periods)
    assert all(p.read_bytes() != b"garbage" for p in cache.glob("__pycache__/*.nb*"))
