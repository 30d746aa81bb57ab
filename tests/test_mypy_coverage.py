"""mypy covers every module: each .py of the packages pyproject's [tool.mypy] names is checked by its
first run (not excluded) or by make lint's second one (a site package named with `-p` there). Only
the students' starting nodes are left out (app/cli/templates/, programs of their own that import
rospy/rclpy): a new package or file cannot slip past both runs."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SITE = "rosclient/site/"


def second_run_packages(makefile: str) -> set[str]:
    """The site packages make lint's second mypy run checks (`cd rosclient/site && mypy ... -p NAME`)."""
    [line] = [line for line in makefile.splitlines() if "cd rosclient/site" in line and "mypy" in line]
    return set(re.findall(r"-p (\w+)", line))


def unchecked(root: Path) -> list[str]:
    config = tomllib.loads((root / "pyproject.toml").read_text())["tool"]["mypy"]
    excluded = [re.compile(pattern) for pattern in config["exclude"]]
    packages = second_run_packages((root / "Makefile").read_text())
    out = []
    for top in config["files"]:
        for path in sorted((root / top).rglob("*.py")):
            name = path.relative_to(root).as_posix()
            if "/__pycache__/" in name or not any(p.search(name) for p in excluded):
                continue
            if name.startswith(SITE) and name[len(SITE) :].split("/")[0] in packages:
                continue
            out.append(name)
    return out


def test_every_module_is_checked_by_one_of_the_two_mypy_runs():
    from app.cli.templates import FILES

    starting_nodes = {f"app/cli/templates/{file}" for file in FILES.values()}
    assert set(unchecked(ROOT)) == starting_nodes
    assert "app/cli/templates/__init__.py" not in unchecked(ROOT)  # the app's code that prints them is checked


def test_a_site_package_in_neither_run_is_found(tmp_path):
    (tmp_path / "rosclient/site/newpkg").mkdir(parents=True)
    (tmp_path / "rosclient/site/newpkg/__init__.py").write_text("")
    (tmp_path / "rosclient/site/rospy").mkdir()
    (tmp_path / "rosclient/site/rospy/core.py").write_text("")
    (tmp_path / "pyproject.toml").write_text(
        '[tool.mypy]\nfiles = ["rosclient"]\nexclude = ["^rosclient/site/(rospy|newpkg)/"]\n'
    )
    (tmp_path / "Makefile").write_text("lint:\n\tcd rosclient/site && mypy -p rospy\n")
    assert unchecked(tmp_path) == ["rosclient/site/newpkg/__init__.py"]
