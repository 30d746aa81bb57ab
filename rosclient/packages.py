"""A program's own packages, as an installed workspace has them: by the names their package.xml
files give (not their folders'), for `from pkg.srv import X` (the package's .msg/.srv/.action),
`import pkg` (its Python package: `pkg/pkg/` as ament_python lays it out, `pkg/src/pkg/` as catkin
does), `$(find pkg)` and a launch file's `<node pkg=...>`.

The workspace is `--workspace DIR` ($HRI_LAB_WORKSPACE), else the one the program is in: above the
nearest folder with a package.xml (its parent; the parent's parent when that is a `src/`). A
program inside a Python package (folders with __init__.py) runs with the package importable
(`from my_pkg.listener import Listener`), as `ros2 run` runs an installed package's entry point.
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from pathlib import Path

MAX_DEPTH = 4  # folders below the workspace searched for package.xml files (src/group/pkg/package.xml)
SKIPPED = {"build", "install", "log", "devel", "node_modules", "__pycache__"}


def package_name(manifest: Path) -> str | None:
    """The <name> of a package.xml (None: unreadable, or no name)."""
    try:
        name = ET.parse(manifest).getroot().findtext("name")
    except (OSError, ET.ParseError):
        return None
    return name.strip() if name and name.strip() else None


def workspace_of(program: Path, workspace: str | None = None) -> Path | None:
    """--workspace DIR, else the workspace of the nearest package.xml above the program (None: no package)."""
    if workspace:
        return Path(workspace).resolve()
    for folder in [program.resolve().parent, *program.resolve().parent.parents]:
        if (folder / "package.xml").is_file():
            parent = folder.parent
            return parent.parent if parent.name == "src" else parent
    return None


def find(workspace: Path | None) -> dict[str, Path]:
    """package name -> its folder, for every package.xml under the workspace (the shallowest first)."""
    found: dict[str, Path] = {}
    if workspace is None or not workspace.is_dir():
        return found
    level = [workspace]
    for _ in range(MAX_DEPTH + 1):
        following = []
        for folder in level:
            manifest = folder / "package.xml"
            name = package_name(manifest) if manifest.is_file() else None
            if name is not None:
                found.setdefault(name, folder)
            try:
                children = sorted(os.scandir(folder), key=lambda e: e.name)
            except OSError:
                continue
            following += [
                Path(c.path)
                for c in children
                if c.is_dir(follow_symlinks=False) and not c.name.startswith(".") and c.name not in SKIPPED
            ]
        level = following
    return found


def python_paths(program: Path, packages: dict[str, Path]) -> list[Path]:
    """What goes on sys.path so that the program's own Python package and its workspace's import
    as installed: above the topmost folder with __init__.py that holds the program, and each
    package's `pkg/` (ament_python) or `src/` (catkin) folder that holds a Python package of its name."""
    paths = []
    folder = program.resolve().parent
    if (folder / "__init__.py").is_file():
        while (folder.parent / "__init__.py").is_file():
            folder = folder.parent
        paths.append(folder.parent)
    for name, directory in packages.items():
        for base in (directory, directory / "src"):
            if (base / name / "__init__.py").is_file() and base not in paths:
                paths.append(base)
    return paths
