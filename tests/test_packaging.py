"""What the wheel installs: the three packages and their subpackages, nothing beside them
(a top-level package of a common name would clash with another distribution's)."""

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
    assert packages == found, (packages ^ found)
