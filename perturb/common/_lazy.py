"""A package's names imported at first use (PEP 562), shared by the three packages.

A command then loads only what it runs: sympy, scipy.optimize and matplotlib stay
out of the commands that need none of them (``tests/test_startup.py``).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable

__all__ = ["lazy_names"]


def lazy_names(package: str, table: dict, namespace: dict) -> tuple[Callable, Callable]:
    """The module-level ``__getattr__`` and ``__dir__`` of ``package`` for ``table``.

    ``table`` maps a name to the relative module that defines it under that name, or
    to ``(module, attribute)``, attribute None for the module itself. A name is
    imported once, then kept in ``namespace`` (the package's ``globals()``).
    """
    def __getattr__(name: str):
        if name not in table:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        module_name, attribute = (table[name], name) if isinstance(table[name], str) \
            else table[name]
        module = importlib.import_module(module_name, package)
        value = module if attribute is None else getattr(module, attribute)
        namespace[name] = value  # imported once
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(table))

    return __getattr__, __dir__
