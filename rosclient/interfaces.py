"""The import finder of a program's process: `from <pkg>.msg import X` (and `.srv`, `.action`) makes
X from its definition (interfaces/packages.py), found in the program's workspace (its folder
and parents, or `--workspace DIR`) first, then in the shipped definitions (interfaces/share).
"""

from __future__ import annotations

import importlib.abc
import importlib.machinery
import sys
import types
from pathlib import Path
from typing import Any

from interfaces.packages import KINDS, Interfaces


class _KindModule(types.ModuleType):
    """`<pkg>.msg` / `.srv` / `.action`: its classes made when first named."""

    def __init__(self, name: str, interfaces: Interfaces, package: str, kind: str) -> None:
        super().__init__(name)
        self._interfaces, self._package, self._kind = interfaces, package, kind

    @property
    def __all__(self) -> list[str]:
        return self._interfaces.names(self._package, self._kind)

    def __getattr__(self, attr: str) -> Any:
        if attr.startswith("__"):
            raise AttributeError(attr)
        value = self._interfaces.get(self._package, self._kind, attr)
        setattr(self, attr, value)
        return value


class Finder(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Imports `<pkg>.msg|srv|action` (and `<pkg>` when nothing else provides it) from definitions."""

    def __init__(self, interfaces: Interfaces) -> None:
        self.interfaces = interfaces

    def find_spec(self, fullname: str, path: Any = None, target: Any = None):
        parts = fullname.split(".")
        if len(parts) == 2 and parts[1] in KINDS and self.interfaces.is_package(parts[0]):
            return importlib.machinery.ModuleSpec(fullname, self, is_package=False)
        if len(parts) == 1 and self.interfaces.is_package(parts[0]):
            spec = importlib.machinery.PathFinder.find_spec(fullname, path)
            if spec is None or spec.origin is None:  # nothing, or a folder without __init__.py
                return importlib.machinery.ModuleSpec(fullname, self, is_package=True)
        return None

    def create_module(self, spec):
        parts = spec.name.split(".")
        if len(parts) == 2:
            return _KindModule(spec.name, self.interfaces, parts[0], parts[1])
        module = types.ModuleType(spec.name)
        module.__path__ = []
        return module

    def exec_module(self, module) -> None:
        return None


def install(roots: list[Path]) -> Interfaces:
    """Put the interface finder first on sys.meta_path (the program's process only)."""
    interfaces = Interfaces(roots)
    sys.meta_path.insert(0, Finder(interfaces))
    return interfaces


def workspace_roots(program: Path, workspace: str | None = None) -> list[Path]:
    """Where a program's own interface packages are: --workspace DIR, else its folder and parents
    (and each one's `src/`, as a colcon/catkin workspace keeps them)."""
    if workspace:
        base = Path(workspace).resolve()
        return [base, base / "src"]
    roots = []
    for folder in [program.resolve().parent, *program.resolve().parent.parents]:
        roots.extend([folder, folder / "src"])
    return roots
