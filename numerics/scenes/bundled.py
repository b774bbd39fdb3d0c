"""The scene files shipped with the toolkit, found by name: the examples for teaching
(``numerics/scenes/examples``, data of the package that runs them) and the paper's
figures (``paper_checks/scenes``).

A bundled scene runs by its name wherever the toolkit is installed
(``python -m numerics scene bouncing``); ``python -m numerics scene --list`` lists
them with their titles.
"""

from __future__ import annotations

import tomllib
from importlib import resources
from pathlib import Path

__all__ = ["bundled_scenes", "find_scene", "scene_list"]

#: Where the bundled scenes are, in the order their names are looked up.
PACKAGES = {"example": "numerics.scenes.examples", "paper": "paper_checks.scenes"}


def bundled_scenes() -> dict[str, tuple[str, Path]]:
    """{name: (kind, path)} of every bundled scene file, the name its stem; an example
    comes before a paper's scene of the same name."""
    found: dict[str, tuple[str, Path]] = {}
    for kind, package in PACKAGES.items():
        for entry in sorted(resources.files(package).iterdir(), key=lambda e: e.name):
            if entry.name.endswith(".toml"):
                found.setdefault(entry.name.removesuffix(".toml"), (kind, Path(str(entry))))
    return found


def find_scene(name_or_path: str | Path) -> Path:
    """The scene file ``name_or_path`` names: a file that exists, else the bundled scene
    of its name (``bouncing`` or ``bouncing.toml``; a path into the repository's scene
    folders, as the docs write them, finds the installed file too). A FileNotFoundError says
    how to list the bundled scenes."""
    path = Path(name_or_path)
    if path.is_file():
        return path
    name = path.name.removesuffix(".toml")
    in_docs = any(folder in path.as_posix()
                  for folder in ("paper_checks/scenes", "numerics/scenes/examples"))
    bundled = bundled_scenes()
    if name in bundled and (path.parent == Path(".") or in_docs):
        return bundled[name][1]
    raise FileNotFoundError(f"no scene file {str(name_or_path)!r}, and no bundled scene of "
                            "that name (`python -m numerics scene --list` lists them)")


def scene_list() -> str:
    """The bundled scenes, one a line: name, kind and title."""
    scenes = bundled_scenes()
    width = max(len(name) for name in scenes)
    lines = []
    for name, (kind, path) in scenes.items():
        title = tomllib.loads(path.read_text(encoding="utf-8")).get("title", name)
        lines.append(f"{name:<{width}}  {kind:<7}  {title}")
    return "\n".join(lines)
