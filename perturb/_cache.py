"""The cache on disk of what is derived from the model, under keys that need no sympy.

Deriving the numbers of Eq. 2.6 and generating the simulator's kernels takes
sympy, and importing sympy alone takes about 0.3 s. Both depend only on the
model (its parameters; the kernels also on its effects) and on the source files
that shape them, so each is written once under a key made of exactly those:
a process that finds them never imports sympy. The files sit in one folder,

    $CONTACT_RESONANCES_CACHE/kernels   or   ~/.cache/contact-resonances/kernels

- ``numbers_KEY.json``: the numbers of Eq. 2.6 at one parameter set
  (``perturb._numbers``), KEY from the parameters;
- ``kernel_KEY.py`` and numba's ``__pycache__/kernel_KEY.*``: the compiled
  simulator of one model (``numerics._codegen``), KEY from the parameters and
  the effects.

Deleting the folder only costs the time to derive and compile again.
"""

from __future__ import annotations

import atexit
import hashlib
import importlib.util
import os
import shutil
import stat
import sys
import tempfile
import warnings
from collections.abc import Iterable
from pathlib import Path
from types import ModuleType

__all__ = ["CacheWarning", "cache_dir", "usable_cache_dir", "cache_key", "write_atomically",
           "MODEL_SOURCES"]

#: The files of ``perturb`` that shape everything derived from the model.
MODEL_SOURCES = tuple(Path(__file__).with_name(name) for name in
                      ("_model.py", "_effects.py", "_parameters.py", "_symbols.py", "_cache.py"))

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
    """16 hex digits of the SHA-256 of ``repr(values)``, the sympy release and the text
    of ``sources``: a change to any of them gives a new key (old files are left)."""
    text = repr(values) + _sympy_release() + "".join(Path(p).read_text() for p in sources)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def write_atomically(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file and a rename, so that a
    parallel process never reads half a file."""
    tmp = path.with_suffix(f".tmp{os.getpid()}")
    tmp.write_text(text)
    tmp.replace(path)


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
