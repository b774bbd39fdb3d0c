"""What the wheel installs: the three packages and their subpackages, nothing beside them
(a top-level package of a common name would clash with another distribution's)."""

import ast
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_the_wheel_installs_the_three_packages_and_every_subpackage_of_theirs():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    packages = set(config["tool"]["setuptools"]["packages"])
    assert {name.split(".")[0] for name in packages} == {"perturb", "numerics", "paper_checks"}
    found = {str(init.parent.relative_to(ROOT)).replace("/", ".")
             for top in ("perturb", "numerics", "paper_checks")
             for init in (ROOT / top).rglob("__init__.py")}
    # The scene files' folders hold data alone: packages of the build, without __init__.
    data = {"paper_checks.scenes", "numerics.scenes.examples"}
    assert packages == found | data, (packages ^ (found | data))
    assert all(any((ROOT / name.replace(".", "/")).glob("*.toml")) for name in data)


def _subpackages(top: str) -> list[Path]:
    return sorted(init.parent for init in (ROOT / top).rglob("__init__.py")
                  if init.parent != ROOT / top)


def test_the_packages_are_split_into_concept_folders_with_few_modules_at_the_root():
    for top in ("perturb", "numerics"):
        root_modules = sorted(p.name for p in (ROOT / top).glob("*.py"))
        assert len(root_modules) <= 8, (top, root_modules)


def test_every_folder_says_what_it_holds_and_exports_names_it_has():
    import importlib

    for top in ("perturb", "numerics"):
        for folder in _subpackages(top):
            name = str(folder.relative_to(ROOT)).replace("/", ".")
            module = importlib.import_module(name)
            assert module.__doc__ and len(module.__doc__.strip()) > 40, name
            for exported in getattr(module, "__all__", ()):
                getattr(module, exported)


def test_no_folder_is_named_like_a_name_its_package_exports():
    # A folder imported sets an attribute of its package: a folder named like an
    # exported function (say `simulate`) would hide that function.
    import importlib

    for top in ("perturb", "numerics"):
        for folder in _subpackages(top):
            parent = str(folder.parent.relative_to(ROOT)).replace("/", ".")
            assert folder.name not in importlib.import_module(parent).__all__, folder


def test_no_private_name_is_imported_across_modules():
    # A name with a leading underscore belongs to its module: another module that
    # needs it should find it public, under a name that says what it is.
    import ast

    crossings = []
    for top in ("perturb", "numerics", "paper_checks"):
        for path in (ROOT / top).rglob("*.py"):
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                if isinstance(node, ast.ImportFrom) and node.module != "__future__":
                    crossings += [(path.name, node.module, alias.name) for alias in node.names
                                  if alias.name.startswith("_") and alias.name != "__version__"]
                elif (isinstance(node, ast.Attribute) and node.attr.startswith("_")
                        and not node.attr.startswith("__") and isinstance(node.value, ast.Name)
                        and node.value.id.startswith("_") and node.value.id != "_"):
                    crossings.append((path.name, node.value.id, node.attr))
    assert not crossings, crossings


def test_the_distribution_says_its_licence():
    # BSD-3-Clause, as an SPDX expression (PEP 639), with the licence's text shipped.
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    assert config["license"] == "BSD-3-Clause" and config["license-files"] == ["LICENSE"]
    assert (ROOT / "LICENSE").read_text(encoding="utf-8").startswith("BSD 3-Clause License")
    assert not any(c.startswith("License ::") for c in config["classifiers"])  # PEP 639


def test_one_walker_serves_every_continuation():
    # Every walk is the one engine's: the walk of a branch (in f_e or P_a, and branch
    # switching, which drives it) and the fold curves' walk subclass ArclengthWalk, and
    # only the engine calls the step routine (whose compiled twin is walk_template's).
    import numerics.continuation.folds as folds
    import numerics.continuation.walk as walk

    assert issubclass(walk.Walk, walk.ArclengthWalk)
    assert issubclass(folds.FoldWalk, walk.ArclengthWalk)
    walkers = [name for module in (walk, folds) for name, value in vars(module).items()
               if isinstance(value, type) and name.endswith("Walk")
               and value.__module__ == module.__name__]
    assert sorted(walkers) == ["ArclengthWalk", "FoldWalk", "Walk"]
    callers = []
    for path in sorted((ROOT / "numerics").rglob("*.py")):
        tree = ast.parse(path.read_text())
        callers += [path.name for node in ast.walk(tree) if isinstance(node, ast.Call)
                    and getattr(node.func, "id", getattr(node.func, "attr", None))
                    == "arclength_step"]
    assert callers == ["walk.py"], callers
