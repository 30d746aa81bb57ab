"""A package's executables as `ros2 run PKG EXE` and `rosrun PKG EXE` find them, in a workspace's
sources (nothing is built or installed here):

- an ament_python package's `console_scripts` entry points (`name = module.path:function`), read
  from its setup.py (without running it: the literal `entry_points` of its `setup(...)` call, names
  assigned at its top level such as `package_name` resolved) or its setup.cfg; `ros2 run` calls the
  function of the installed script that colcon makes of each;
- else a file of that name anywhere in the package, as rosrun finds it (`find PKG -name EXE`):
  `scripts/`, `nodes/`, `src/PKG/`, ... (the nearest first).

Where the workspace is: ROS finds packages through the setup file a student sources
(AMENT_PREFIX_PATH / ROS_PACKAGE_PATH); here, in order: `--workspace DIR` ($HRI_LAB_WORKSPACE), the
workspaces above the working folder (a folder with a package.xml under it, or a `src/` holding
packages: `~/ros2_ws`, `~/catkin_ws/src/PKG`), each folder of $ROS_PACKAGE_PATH, then the home
folder's `*_ws` workspaces (colcon's and catkin's naming), so that `hri-lab run PKG EXE` works
from any folder as it does once `install/setup.bash` is sourced.

`main_call` says whether a program file defines `main()` without calling it (no
`if __name__ == "__main__":` block): `ros2 run` would call it as an entry point, so `hri-lab run
FILE.py` does too, and says so.
"""

from __future__ import annotations

import ast
import configparser
import os
from dataclasses import dataclass
from pathlib import Path

from rosclient import packages

WORKSPACE_ENV = "HRI_LAB_WORKSPACE"
MAX_SEARCHED = 20_000  # files looked at for a rosrun-style executable (a huge folder is not walked whole)
MAX_SETUP_CHARS = 1_000_000  # a setup.py / setup.cfg longer than this is not read


class NotFound(Exception):
    """No such package or executable: the message `ros2 run` / `rosrun` would print."""


@dataclass(frozen=True)
class Executable:
    package: str
    name: str
    folder: Path  # the package's folder (its package.xml)
    workspace: Path  # the workspace it was found in (its interface packages are found there)
    script: Path | None = None  # a program file run as __main__ (rosrun, an installed script)
    entry: str | None = None  # "module.path:function" (a console_scripts entry point)
    root: Path | None = None  # where the entry point's top-level module imports from

    @property
    def program(self) -> Path:
        """The file that stands for it: the script, or the entry point's module file."""
        if self.script is not None:
            return self.script
        assert self.entry is not None and self.root is not None  # one of the two is set
        module = self.entry.partition(":")[0].split(".")
        base = self.root.joinpath(*module)
        return base.with_suffix(".py") if base.with_suffix(".py").is_file() else base / "__init__.py"


# --- where the workspaces are --------------------------------------------------------------------
def workspaces(cwd: Path, workspace: str | None = None, env: dict[str, str] | None = None) -> list[Path]:
    """The folders searched for packages, in order (see the module's docstring)."""
    env = dict(os.environ) if env is None else env
    found: list[Path] = []

    def add(folder: Path) -> None:
        folder = folder.resolve()
        if folder.is_dir() and folder not in found:
            found.append(folder)

    for given in (workspace, env.get(WORKSPACE_ENV)):
        if given:
            add(Path(given).expanduser())
    cwd = cwd.resolve()
    for folder in [cwd, *cwd.parents]:
        if (folder / "package.xml").is_file():
            parent = folder.parent
            add(parent.parent if parent.name == "src" else parent)
        elif (folder / "src").is_dir() and folder != Path(folder.anchor) and _holds_packages(folder / "src"):
            add(folder)
    for entry in env.get("ROS_PACKAGE_PATH", "").split(os.pathsep):
        if entry:
            add(Path(entry).expanduser())
    home = Path(env.get("HOME") or Path.home())
    try:
        homes = sorted(home.glob("*_ws"))
    except OSError:
        homes = []
    for folder in homes:
        if (folder / "src").is_dir():
            add(folder)
    return found


def _holds_packages(src: Path) -> bool:
    """A `src/` with a package.xml one or two levels down (a workspace's, not any project's src/)."""
    try:
        return any(src.glob("*/package.xml")) or any(src.glob("*/*/package.xml"))
    except OSError:
        return False


def find_package(name: str, roots: list[Path]) -> tuple[Path, Path] | None:
    """(the package's folder, its workspace) of the first root that has it by its package.xml name."""
    for root in roots:
        named = packages.find(root)
        if name in named:
            return named[name], root
    return None


# --- entry points -----------------------------------------------------------------------------------
def entry_points(folder: Path) -> dict[str, str]:
    """console_scripts name -> "module:function" of a package's setup.py and setup.cfg."""
    found: dict[str, str] = {}
    for line in _setup_cfg_scripts(folder / "setup.cfg") + _setup_py_scripts(folder / "setup.py"):
        name, sep, target = line.partition("=")
        target = target.split("[")[0].strip()  # `name = mod:func [extra]`
        if sep and name.strip() and ":" in target:
            found.setdefault(name.strip(), target.replace(" ", ""))
    return found


def _read(path: Path) -> str | None:
    try:
        if not path.is_file() or path.stat().st_size > MAX_SETUP_CHARS:
            return None
        return path.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return None


def _setup_cfg_scripts(path: Path) -> list[str]:
    text = _read(path)
    if text is None:
        return []
    parser = configparser.ConfigParser(interpolation=None)
    try:
        parser.read_string(text)
        value = parser.get("options.entry_points", "console_scripts", fallback="")
    except configparser.Error:
        return []
    return [line.strip() for line in value.splitlines() if line.strip()]


class _NotLiteral(Exception):
    pass


def _setup_py_scripts(path: Path) -> list[str]:
    text = _read(path)
    if text is None:
        return []
    try:
        tree = ast.parse(text)
    except (SyntaxError, ValueError):
        return []
    names: dict[str, object] = {}
    for statement in tree.body:  # `package_name = 'lab8'` and the like, in order
        if isinstance(statement, ast.Assign) and len(statement.targets) == 1:
            target = statement.targets[0]
            if isinstance(target, ast.Name):
                try:
                    names[target.id] = _literal(statement.value, names)
                except _NotLiteral:
                    names.pop(target.id, None)
    for node in ast.walk(tree):
        if not (isinstance(node, ast.Call) and _called(node) == "setup"):
            continue
        for keyword in node.keywords:
            if keyword.arg != "entry_points":
                continue
            try:
                value = _literal(keyword.value, names)
            except _NotLiteral:
                return []
            scripts = value.get("console_scripts", []) if isinstance(value, dict) else []
            if isinstance(scripts, str):
                scripts = scripts.splitlines()
            return [s.strip() for s in scripts if isinstance(s, str) and s.strip()]
    return []


def _called(call: ast.Call) -> str | None:
    if isinstance(call.func, ast.Name):
        return call.func.id
    if isinstance(call.func, ast.Attribute):
        return call.func.attr
    return None


def _literal(node: ast.AST, names: dict[str, object]) -> object:
    """A setup.py expression made only of literals, known names, `+`, `%`, f-strings and `.format`."""
    if isinstance(node, ast.Constant):
        return node.value
    if isinstance(node, ast.Name):
        if node.id in names:
            return names[node.id]
        raise _NotLiteral(node.id)
    if isinstance(node, ast.List | ast.Tuple):
        return [_literal(e, names) for e in node.elts]
    if isinstance(node, ast.Dict):
        return {_literal(k, names): _literal(v, names) for k, v in zip(node.keys, node.values) if k is not None}
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add | ast.Mod):
        left, right = _literal(node.left, names), _literal(node.right, names)
        try:
            return left + right if isinstance(node.op, ast.Add) else left % right  # type: ignore[operator]
        except TypeError:
            raise _NotLiteral("operands") from None
    if isinstance(node, ast.JoinedStr):
        return "".join(str(_literal(v, names)) for v in node.values)
    if isinstance(node, ast.FormattedValue):
        return _literal(node.value, names)
    if (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and node.func.attr == "format"
        and not node.keywords
    ):
        base = _literal(node.func.value, names)
        if isinstance(base, str):
            return base.format(*(_literal(a, names) for a in node.args))
    raise _NotLiteral(type(node).__name__)


def module_root(folder: Path, module: str) -> Path | None:
    """Where `module`'s top-level package imports from in the package's sources (the package's
    folder as ament_python lays it out, or its src/)."""
    top = module.split(".")[0]
    for base in (folder, folder / "src"):
        if (base / top / "__init__.py").is_file() or (base / f"{top}.py").is_file() or (base / top).is_dir():
            return base
    return None


# --- rosrun's search ----------------------------------------------------------------------------------
def package_files(folder: Path, name: str) -> list[Path]:
    """The files called `name` in a package (the shallowest first), as rosrun's `find` finds them."""
    found: list[Path] = []
    level, seen = [folder], 0
    while level and seen < MAX_SEARCHED:
        following: list[Path] = []
        for current in level:
            try:
                entries = sorted(os.scandir(current), key=lambda e: e.name)
            except OSError:
                continue
            for entry in entries:
                seen += 1
                if entry.name.startswith(".") or entry.name in packages.SKIPPED:
                    continue
                if entry.is_dir(follow_symlinks=False):
                    following.append(Path(entry.path))
                elif entry.name == name and entry.is_file():
                    found.append(Path(entry.path))
        level = following
    return found


def resolve(package: str, name: str, roots: list[Path]) -> Executable:
    """The executable `name` of `package` (NotFound with ros2 run's words when there is none)."""
    where = find_package(package, roots)
    if where is None:
        searched = ", ".join(str(r) for r in roots) or "none found"
        raise NotFound(
            f"Package '{package}' not found (workspaces searched: {searched}; give one with --workspace DIR "
            f"or ${WORKSPACE_ENV})"
        )
    folder, workspace = where
    scripts = entry_points(folder)
    if name in scripts:
        entry = scripts[name]
        root = module_root(folder, entry.partition(":")[0])
        if root is None:
            raise NotFound(
                f"Executable '{name}' of package '{package}' is the entry point {entry}, and its module is not in "
                f"{folder}"
            )
        return Executable(package, name, folder, workspace, entry=entry, root=root)
    files = package_files(folder, name)
    if files:
        return Executable(package, name, folder, workspace, script=files[0])
    known = sorted(scripts)
    hint = f" (its entry points: {', '.join(known)})" if known else ""
    raise NotFound(f"No executable found: '{name}' in package '{package}' at {folder}{hint}")


# --- a program file with main() and no __main__ block ---------------------------------------------------
def main_call(source: str) -> str | None:
    """None when the program runs by itself as __main__; else why main() is to be called, or why
    it cannot be ("main() needs arguments")."""
    try:
        tree = ast.parse(source)
    except (SyntaxError, ValueError):
        return None
    main = None
    for statement in tree.body:
        if isinstance(statement, ast.FunctionDef | ast.AsyncFunctionDef) and statement.name == "main":
            main = statement
        elif isinstance(statement, ast.If) and any(
            isinstance(n, ast.Name) and n.id == "__name__" for n in ast.walk(statement.test)
        ):
            return None
        elif any(isinstance(n, ast.Call) and _called(n) == "main" for n in ast.walk(statement)):
            return None  # main() called at the top level (or by something it starts)
    if main is None or isinstance(main, ast.AsyncFunctionDef):
        return None
    arguments = main.args
    required = len(arguments.posonlyargs) + len(arguments.args) - len(arguments.defaults)
    required += sum(1 for d in arguments.kw_defaults if d is None)
    if required > 0:
        return "needs arguments"
    return "call"
