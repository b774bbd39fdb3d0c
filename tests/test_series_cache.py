"""The series' formulas on disk (``perturb.series.compiled``, issue 12): a later process imports
them instead of deriving, they compute exactly what the derivation's lambdified code
computes, and a cut or garbled file is derived again."""

import numpy as np
import pytest

from perturb.cache import write_generated
from perturb.series import compiled
from perturb.series.compiled import formulas_cached

# Eq. 2.6's series, the one whose lambdified formulas are kept on disk.
compile_series = compiled.lambdified_series

ORDER = 4
#: (A0, omega, Omega, c, h): dimensionless values, as tests/test_perturb_series.py uses.
ARGUMENTS = (1.0, np.array([1.0, 0.9]), np.array([0.45, 0.95]), 0.04, 0.3)


@pytest.fixture
def empty_cache(tmp_path, monkeypatch):
    """An empty cache folder, and no formulas remembered by this process."""
    monkeypatch.setenv("CONTACT_RESONANCES_CACHE", str(tmp_path))
    compile_series.cache_clear()
    yield tmp_path / "kernels"
    compile_series.cache_clear()


def _not_derived(order):
    raise AssertionError(f"order {order} derived again, not read from the cache")


def _values(formulas):
    env = formulas.evaluate(*ARGUMENTS)
    return {name: env[name] for name in sorted(env)}


def test_cached_formulas_compute_what_the_derivation_computes(empty_cache, monkeypatch):
    assert not formulas_cached(ORDER)
    derived = compile_series(ORDER)
    assert formulas_cached(ORDER)
    compile_series.cache_clear()
    monkeypatch.setattr(compiled, "derive", _not_derived)
    loaded = compile_series(ORDER)
    assert (loaded.order, loaded.b_orders, loaded.keys) == (
        derived.order, derived.b_orders, derived.keys)
    assert [(s.name, s.kind, s.inputs) for s in loaded.steps] == [
        (s.name, s.kind, s.inputs) for s in derived.steps]
    expected, found = _values(derived), _values(loaded)
    assert found.keys() == expected.keys()
    for name in expected:  # the same code: bit for bit
        np.testing.assert_array_equal(found[name], expected[name], err_msg=name)


@pytest.mark.parametrize("damage", ["cut", "garbled"])
def test_a_damaged_formulas_file_is_derived_again(empty_cache, damage):
    compile_series(ORDER)
    path, = empty_cache.glob("formulas_*.py")
    text = path.read_text()
    if damage == "cut":
        path.write_text(text[: len(text) // 2])
    else:  # whole by its checksum, but not the formulas of its order: the import checks
        write_generated(path, text.partition("\n")[2].replace("ORDER = 4", "ORDER = 5"))
        assert formulas_cached(ORDER)
    compile_series.cache_clear()
    again = compile_series(ORDER)
    assert again.order == ORDER and formulas_cached(ORDER)
    assert path.read_text() == text  # written anew


def test_the_reports_warm_up_writes_every_order_and_keeps_none_in_memory(empty_cache):
    # paper_checks derives the formulas in a worker while the kernels compile; the
    # work-precision study may run next in that worker and times each order's first
    # call, which must then be the import from the disk, not a look-up in memory.
    from paper_checks.scene import _derive_formulas
    from paper_checks.work_precision import ERROR_ORDERS, SERIES_ORDERS

    _derive_formulas()
    assert compile_series.cache_info().currsize == 0
    assert all(formulas_cached(n) for n in range(max(SERIES_ORDERS) + ERROR_ORDERS + 1))


def test_formulas_that_cannot_be_written_are_still_given(empty_cache, monkeypatch):
    # A full disk: the derived formulas are returned, with a warning, and not cached.
    from perturb.cache import CacheWarning

    def full_disk(path, body):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(compiled, "write_generated", full_disk)
    with pytest.warns(CacheWarning, match="order 2 are not cached"):
        formulas = compile_series(2)
    assert formulas.order == 2 and not formulas_cached(2)


def test_the_work_precision_study_times_first_calls_and_says_where_from(empty_cache):
    # Another scene may have filled this worker's memory (the comparison evaluates the
    # same orders): the study empties it, then each order is imported from the disk.
    from paper_checks.work_precision import _compile_orders

    for order in range(3):
        compile_series(order)  # on the disk and in memory
    seconds, cached = _compile_orders(2)
    assert cached == [True, True, True]
    assert min(seconds) > 1e-5  # imports (about 1 ms each), not look-ups (about 1e-6 s)
