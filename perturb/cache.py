"""The cache on disk of what is derived from the model, under keys that need no sympy.

Deriving the numbers of Eq. 2.6 and generating the simulator's kernels takes
sympy, and importing sympy alone takes about 0.3 s. Both depend only on the
model (its parameters; the kernels also on its effects) and on the source files
that shape them, so each is written once under a key made of exactly those (the
files' code: an edit of a comment or a docstring changes no key): a process that
finds them never imports sympy. The files sit in one folder,

    $CONTACT_RESONANCES_CACHE/kernels   or   ~/.cache/contact-resonances/kernels

- ``numbers_KEY.json``: the numbers of Eq. 2.6 at one parameter set
  (``perturb.model.numbers``), KEY from the parameters;
- ``kernel_KEY.py`` and numba's ``__pycache__/kernel_KEY.*``: the compiled
  simulator of one model (``numerics.kernels.codegen``), KEY from the parameters and
  the effects; ``walk_KEY.py`` its continuation walk (``numerics.kernels.walk_codegen``),
  ``series_KEY.py`` the series' kernels of one order (``perturb.response.codegen``);
- ``formulas_KEY.py``: the series' lambdified formulas of one order
  (``perturb.series.compiled``), KEY from the order and the series' sources.

A generated module is written with the checksum of its text as its first line and
loaded by ``load_generated``: a file that is cut short, emptied or edited, or whose
numba cache does not load, is written and compiled again. Deleting the folder only
costs the time to derive and compile again.
"""

from __future__ import annotations

import ast
import atexit
import hashlib
import importlib.util
import os
import shutil
import stat
import sys
import tempfile
import warnings
from collections.abc import Callable, Iterable
from pathlib import Path
from types import ModuleType

from perturb.common._files import write_atomically

__all__ = ["CacheWarning", "cache_dir", "usable_cache_dir", "cache_key", "write_atomically",
           "MODEL_SOURCES", "SERIES_SOURCES", "load_generated", "write_generated", "intact",
           "remove_generated", "machine_code_index"]

#: The files of ``perturb`` that shape everything derived from the model.
MODEL_SOURCES = (*(Path(__file__).parent / "model" / name for name in
                   ("contact_model.py", "effects.py", "parameters.py", "symbols.py")),
                 Path(__file__))
#: The files whose code shapes the series' formulas (``perturb.series.compiled``) and the
#: response kernels generated from them (``perturb.response.codegen``).
SERIES_SOURCES = (*MODEL_SOURCES, Path(__file__).parent / "model" / "eq26.py",
                  *(Path(__file__).parent / "series" / name for name in (
                      "lindstedt.py", "harmonics.py", "series_symbols.py", "compiled.py")))

_WARNED: set[Path] = set()


class CacheWarning(UserWarning):
    """The cache could not be used as configured; a fallback is used instead."""


def cache_dir() -> Path:
    """Folder of the cache: $CONTACT_RESONANCES_CACHE/kernels, else
    ~/.cache/contact-resonances/kernels."""
    root = os.environ.get("CONTACT_RESONANCES_CACHE")
    base = Path(root) if root else Path.home() / ".cache" / "contact-resonances"
    return base / "kernels"


def _writable(folder: Path) -> bool:
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=folder):
            return True
    except OSError:
        return False


def usable_cache_dir() -> Path:
    """``cache_dir()`` if files can be written there, else a private temporary folder
    (with a one-line ``CacheWarning``, once per folder and process): everything still
    works, it is derived and compiled again."""
    folder = cache_dir()
    if _writable(folder):
        return folder
    fallback = _private_temporary_folder() / "kernels"
    if folder not in _WARNED:
        _WARNED.add(folder)
        warnings.warn(f"kernel cache {str(folder)!r} is not writable; using {str(fallback)!r}",
                      CacheWarning, stacklevel=3)
    fallback.mkdir(exist_ok=True)
    return fallback


_PRIVATE: list[Path] = []  # this process's own temporary folder, once made


def _private_temporary_folder() -> Path:
    """A temporary folder that only this user can write: ``contact-resonances-UID`` in the
    system's temporary folder, if this user owns it, it is no link and no one else may
    write it (the cache's files are imported and unpickled: another user's files there
    would run their code); else a new folder of this process's own."""
    if _PRIVATE:  # chosen once per process
        return _PRIVATE[0]
    shared = Path(tempfile.gettempdir()) / f"contact-resonances-{os.getuid()}"
    try:
        shared.mkdir(mode=0o700, exist_ok=True)
        status = os.lstat(shared)
        if stat.S_ISDIR(status.st_mode) and status.st_uid == os.getuid():
            if not status.st_mode & 0o022:
                return shared
            # This user's, but others may have written into it (an older release made
            # it with the umask's mode): its files cannot be trusted, nor closed after.
            warnings.warn(f"{str(shared)!r} can be written by others, so it is not used "
                          f"(remove it, or `chmod 700` it if only you wrote to it); the "
                          f"kernels are compiled in a folder of this process's own",
                          CacheWarning, stacklevel=4)
    except OSError:
        pass
    _PRIVATE.append(Path(tempfile.mkdtemp(prefix="contact-resonances-")))
    atexit.register(shutil.rmtree, _PRIVATE[0], True)  # nothing reuses it
    return _PRIVATE[0]


def _sympy_release() -> str:
    """The text of sympy's release.py (its version), found without importing sympy."""
    spec = importlib.util.find_spec("sympy")
    return (Path(spec.origin).parent / "release.py").read_text()


def cache_key(values: object, sources: Iterable[Path]) -> str:
    """16 hex digits of the SHA-256 of ``repr(values)``, the sympy release and the code
    of ``sources`` (``code_of``): a change to any of them gives a new key (old files are
    left); an edit of a comment, a docstring or the layout gives none."""
    text = repr(values) + _sympy_release() + "".join(code_of(Path(p)) for p in sources)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def code_of(path: Path) -> str:
    """The code of a Python file, without what compiles to nothing: its syntax tree
    (comments and layout are not in it) with every docstring dropped, as text."""
    tree = ast.parse(path.read_text(), filename=str(path))
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
                    and isinstance(body[0].value.value, str):
                node.body = body[1:] or [ast.Pass()]
    return ast.dump(tree)


def _checksum(body: str) -> str:
    return "# sha256 " + hashlib.sha256(body.encode()).hexdigest()


def write_generated(path: Path, body: str) -> None:
    """Write the generated module ``body`` to ``path`` (atomically), with the checksum of
    ``body`` as its first line (``intact`` checks it)."""
    write_atomically(path, f"{_checksum(body)}\n{body}")


def intact(path: Path) -> bool:
    """Whether the file at ``path`` holds all the source it was written with by
    ``write_generated`` (its first line is the checksum of the rest): a missing,
    truncated, emptied or edited file is not."""
    try:
        head, _, body = path.read_text().partition("\n")
    except (OSError, UnicodeDecodeError):
        return False
    return head == _checksum(body)


def machine_code_index(path: Path, function: str = "*") -> Path | None:
    """numba's index file of the machine code it cached for ``function`` (any, by
    default) of the generated module at ``path`` (``__pycache__/STEM.FUNCTION-*.nbi``
    beside it), or None: whether that function is compiled on disk."""
    return next(path.parent.glob(f"__pycache__/{path.stem}.{function}-*.nbi"), None)


def remove_generated(path: Path) -> None:
    """Remove the generated module at ``path`` and numba's machine code cached for it
    (``__pycache__/STEM.*`` beside it)."""
    for stale in [path, *path.parent.glob(f"__pycache__/{path.stem}.*")]:
        stale.unlink(missing_ok=True)


def load_generated(path: Path, name: str, source: Callable[[], str],
                   smoke: Callable[[ModuleType], None]) -> ModuleType:
    """The generated module at ``path``, imported as ``name``: written first (from
    ``source()``, the module's text) if it is missing or not ``intact`` (a crash while
    writing, a full disk, an edit), then imported and ``smoke``-tested
    (``import_generated``). If that fails (e.g. numba's cache files beside an intact
    file are garbled), the file and numba's files of it are removed, written and
    imported once more; an error then is raised.

    Parameters
    ----------
    path : Path
        The module's file in the cache folder (its name holds the cache key).
    name : str
        The module's name in ``sys.modules`` (another generated module may import it).
    source : callable
        Returns the module's text (without the checksum line); called only to write it.
    smoke : callable
        Called with the imported module; calls each compiled function once with the
        argument types of the real calls, so that numba loads their machine code now.
    """
    if path.exists() and not intact(path):
        remove_generated(path)  # cut short, emptied or edited: its machine code too
    if not path.exists():
        write_generated(path, source())
    try:
        return import_generated(path, name, smoke)
    except Exception:  # e.g. a garbled numba cache beside an intact file: rebuilt once
        remove_generated(path)
        write_generated(path, source())
        return import_generated(path, name, smoke)


def import_generated(path: Path, name: str, smoke) -> ModuleType:
    """Import the generated module at ``path`` as ``name`` and call ``smoke(module)``
    (which makes numba load its machine code); on any error the module is forgotten
    and the error raised, for the caller to rebuild."""
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
        smoke(module)
    except Exception:
        sys.modules.pop(name, None)
        raise
    return module
