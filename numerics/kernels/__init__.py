"""The compiled kernels: the model's right-hand side generated, compiled and cached.

- ``codegen``: the acceleration of a model's chosen effects, lambdified and written
  with the RK4 kernels of ``kernel_template`` (and the compiled sweep of
  ``sweep_template``) into one module of the cache folder, compiled by numba once;
- ``lanes``: the Python-numba boundary of one kernel call (``Lanes``, the drive table);
- ``walk_codegen`` and ``walk_template``: continuation's steps in one compiled call.

Everything else in ``numerics`` calls the kernels through these names; users rarely
need them (tests and benchmarks do).
"""

from perturb.common import lazy_names

# Imported at first use (PEP 562): importing one module of the folder loads no other.
_LAZY = {
    "compiled_kernels": ".codegen",
    "kernels_built": ".codegen",
    "acceleration_source": ".codegen",
    "Lanes": ".lanes",
    "Recording": ".lanes",
    "drive_table": ".lanes",
    "compiled_walk": ".walk_codegen",
}

__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())

__all__ = [
    "Lanes",
    "Recording",
    "acceleration_source",
    "compiled_kernels",
    "compiled_walk",
    "drive_table",
    "kernels_built",
]
