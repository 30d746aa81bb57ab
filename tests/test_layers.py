"""The layers read one way (docs/design.md, Layers): sim/ never imports app/, fastapi or viser; inside
sim/, the procedures (experiment, grading) sit above the world and nothing below imports them; and
no module of sim/ or app/ imports itself back through others (an import circle), nor does a package:
inside every package, its subpackages and modules (each taken whole) import one another one way.
The imports are read from the sources (ast), top-level and inside functions alike, so a lazy import
does not hide an arrow. The checker is tested on a made-up tree with circles, so that it cannot pass
by seeing nothing.

The student-side client (rosclient/, its site/ of rospy, rclpy, ... included) is a package of its own: it
imports the message vocabulary both sides share (interfaces/) and nothing of the lab's server, its
grading or the simulation; the server (everything but the commands, app/cli/) never imports it, nor the client
libraries a program imports (rospy, rclpy, ...). Those libraries import one another one way when
they run (an import under TYPE_CHECKING, for annotations alone, is no arrow).

A world is a plug-in (app/worlds/contract.py): nothing outside a world's own package imports it but the
registry (app/serving/worlds.py) and the commands named in WORLD_SPECIFIC."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
# programs of their own, run with other imports on sys.path: students' handouts and the rospy/rclpy shims
NOT_MODULES = ("app/cli/templates/", "rosclient/site/")
NEVER_IN_SIM = ("app", "fastapi", "starlette", "uvicorn", "viser")
PACKAGES = ("sim", "interfaces", "app", "rosclient")  # the lab's top-level packages, the layers upward
CLIENT = "rosclient"
SITE = ROOT / CLIENT / "site"  # the client libraries a program imports under their own names
NEVER_IN_CLIENT = ("sim", "app")  # the client takes only the shared vocabulary (interfaces)
COMMANDS = "app.cli"  # the composition of everything: `hri-lab run` starts the client, `hri-lab launch` its nodes
# The package arrows that run the wrong way today, each named with what cuts it (issue 34, after the
# merges): left out of the package check so that any other package circle fails; one that is gone
# fails too, so that this list stays true.
KNOWN_UPWARD: dict[tuple[str, str], str] = {}  # an arrow up kept for now, with why (none left)
WORLDS = ("app.lab", "app.mobile")  # the worlds' packages (app/serving/worlds.py registers them)
REGISTRY = "app.serving.worlds"
# modules outside a world's package that name it, each with why
WORLD_SPECIFIC: dict[str, str] = {
    "app.cli.experiment": "`hri-lab experiment`: the lifting world's headless trials with its parameter overrides",
}


def modules(root: Path, packages: tuple[str, ...], every: bool = False) -> dict[str, Path]:
    """Every module of the packages under root, by dotted name (a package by its __init__); with
    `every`, the programs of their own too (NOT_MODULES: the client's site, the handouts)."""
    found = {}
    for package in packages:
        for path in sorted((root / package).rglob("*.py")):
            relative = path.relative_to(root).as_posix()
            if relative.startswith(NOT_MODULES) and not every:
                continue
            parts = relative[: -len(".py")].split("/")
            found[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return found


def _type_checking(test: ast.expr) -> bool:
    """`if TYPE_CHECKING:` or `if typing.TYPE_CHECKING:`."""
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def _walk(tree: ast.AST, at_run_time: bool) -> list[ast.AST]:
    """ast.walk's nodes; `at_run_time`: without the body of an `if TYPE_CHECKING:` (its else runs)."""
    found, todo = [], [tree]
    while todo:
        node = todo.pop()
        found.append(node)
        for child in ast.iter_child_nodes(node):
            if at_run_time and isinstance(child, ast.If) and _type_checking(child.test):
                todo.extend(child.orelse)
            else:
                todo.append(child)
    return found


def _imports(name: str, path: Path, at_run_time: bool = False) -> list[tuple[str, str]]:
    """(module, name) of each import of the module, anywhere in it: `import a.b` is ("a.b", ""),
    `from a import b` ("a", "b"); relative imports made absolute. `at_run_time`: not those an
    `if TYPE_CHECKING:` imports for annotations alone."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    pairs = []
    for node in _walk(ast.parse(path.read_text(), str(path)), at_run_time):
        if isinstance(node, ast.Import):
            pairs += [(alias.name, "") for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(anchor + ([base] if base else []))
            pairs += [(base, alias.name) for alias in node.names]
    return pairs


def imported(name: str, path: Path) -> set[str]:
    """The dotted names the module imports, anywhere in it; relative imports made absolute."""
    return {n for base, member in _imports(name, path) for n in ((base, f"{base}.{member}") if member else (base,))}


def import_graph(root: Path, packages: tuple[str, ...]) -> dict[str, set[str]]:
    """Module -> the project's modules it imports (`from a import b` is a.b when b is a module, else a)."""
    known = modules(root, packages)
    return {name: {n for n in imported(name, path) if n in known and n != name} for name, path in known.items()}


def site_graph(site: Path) -> dict[str, set[str]]:
    """The client libraries' modules (rosclient/site/: rospy, rclpy, launch, ..., each imported by
    its own name) -> the site's modules each imports when it runs: `from a import b` is a.b when b
    is a module, else a (a package's __init__ that imports its modules is no circle with them)."""
    known = modules(site, tuple(sorted(p.name for p in site.iterdir() if (p / "__init__.py").is_file())))
    graph = {}
    for name, path in known.items():
        targets = {
            f"{base}.{member}" if member and f"{base}.{member}" in known else base
            for base, member in _imports(name, path, at_run_time=True)
        }
        graph[name] = {t for t in targets if t in known and t != name}
    return graph


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected groups of more than one module (Tarjan): each holds an import circle."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for other in sorted(graph.get(node, ())):
            if other not in index:
                visit(other)
                low[node] = min(low[node], low[other])
            elif other in on_stack:
                low[node] = min(low[node], index[other])
        if low[node] == index[node]:
            group = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                group.append(member)
                if member == node:
                    break
            if len(group) > 1:
                found.append(sorted(group))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return found


def package_graphs(root: Path, packages: tuple[str, ...]) -> dict[str, dict[str, set[str]]]:
    """Package -> the import graph of its members (its subpackages and modules, each taken whole,
    named by its dotted name): a member imports another when any module in it imports any in the other."""
    graph = import_graph(root, packages)
    names = modules(root, packages)
    out: dict[str, dict[str, set[str]]] = {}
    for package in (name for name, path in names.items() if path.name == "__init__.py"):
        depth = package.count(".") + 1

        def member(module: str, package: str = package, depth: int = depth) -> str | None:
            return ".".join(module.split(".")[: depth + 1]) if module.startswith(package + ".") else None

        members: dict[str, set[str]] = {}
        for name, imports in graph.items():
            if (source := member(name)) is not None:
                members.setdefault(source, set())
                members[source] |= {target for n in imports if (target := member(n)) not in (None, source)}
        out[package] = members
    return out


def package_circles(graphs: dict[str, dict[str, set[str]]], cut: set[tuple[str, str]]) -> dict[str, list[list[str]]]:
    """The circles among each package's members, the arrows in `cut` left out."""
    found = {}
    for package, members in graphs.items():
        kept = {a: {b for b in targets if (a, b) not in cut} for a, targets in members.items()}
        if groups := circles(kept):
            found[package] = groups
    return found


def test_sim_never_imports_the_server_or_its_libraries():
    wrong = {
        name: sorted(n for n in imported(name, path) if n.split(".")[0] in NEVER_IN_SIM)
        for name, path in modules(ROOT, ("sim",)).items()
    }
    assert {name: names for name, names in wrong.items() if names} == {}


def client_imports(root: Path, site: Path) -> tuple[dict[str, list[str]], dict[str, list[str]]]:
    """(the client's modules, its site's included, that import the server or the simulation;
    the server's modules that import the client or a library of its site), each with those names."""
    site_names = {path.name for path in site.iterdir() if path.is_dir()} if site.is_dir() else set()
    client = {
        name: sorted(n for n in imported(name, path) if n.split(".")[0] in NEVER_IN_CLIENT)
        for name, path in modules(root, (CLIENT,), every=True).items()
    }
    servers = tuple(p for p in PACKAGES if p != CLIENT)
    server = {
        name: sorted(n for n in imported(name, path) if n.split(".")[0] in {CLIENT, *site_names})
        for name, path in modules(root, servers, every=True).items()
        if not (name == COMMANDS or name.startswith(COMMANDS + "."))
    }
    return {n: v for n, v in client.items() if v}, {n: v for n, v in server.items() if v}


def test_the_client_and_the_server_never_import_each_other():
    assert client_imports(ROOT, SITE) == ({}, {})


def test_nothing_below_the_procedures_imports_them():
    graph = import_graph(ROOT, ("sim",))
    upward = {
        name: sorted(n for n in names if n.startswith("sim.procedures"))
        for name, names in graph.items()
        if not name.startswith("sim.procedures")
    }
    assert {name: names for name, names in upward.items() if names} == {}


def world_imports(root: Path, packages: tuple[str, ...], worlds: tuple[str, ...]) -> dict[str, list[str]]:
    """The modules outside a world's own package that import one of the worlds' packages, with what."""
    found = {}
    for name, imports in import_graph(root, packages).items():
        own = next((w for w in worlds if name == w or name.startswith(w + ".")), None)
        named = sorted({w for n in imports for w in worlds if w != own and (n == w or n.startswith(w + "."))})
        if named:
            found[name] = named
    return found


def test_nothing_but_the_registry_names_a_world():
    found = world_imports(ROOT, PACKAGES, WORLDS)
    assert set(found) - {REGISTRY, *WORLD_SPECIFIC} == set()
    assert found[REGISTRY] == sorted(WORLDS)  # every world registered
    assert set(WORLD_SPECIFIC) <= set(found), "these no longer name a world: take them out of WORLD_SPECIFIC"


def test_the_checker_finds_a_world_imported_from_outside(tmp_path):
    for relative, text in {
        "app/__init__.py": "",
        "app/lab/__init__.py": "",
        "app/lab/world.py": "from app.lab import topics\n",
        "app/lab/topics.py": "",
        "app/rosbridge/__init__.py": "",
        "app/rosbridge/bridge.py": "def f():\n    from app.lab.topics import TOPICS\n",
    }.items():
        (tmp_path / relative).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / relative).write_text(text)
    assert world_imports(tmp_path, ("app",), ("app.lab",)) == {"app.rosbridge.bridge": ["app.lab"]}


def test_no_import_circle_in_the_lab():
    assert list(circles(import_graph(ROOT, PACKAGES))) == []


def test_no_import_circle_in_the_client_libraries():
    """rosclient/site's libraries import one another one way when they run. An import under
    TYPE_CHECKING names a type for annotations alone (rclpy's executors and nodes name each other
    so, as upstream rclpy's do) and is no arrow."""
    assert circles(site_graph(SITE)) == []


def test_the_site_checker_finds_a_circle_a_lazy_import_makes_and_not_an_annotations_one(tmp_path):
    files = {
        "lib/__init__.py": "",
        "lib/node.py": "from lib.client import Client\n",
        "lib/client.py": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from lib.node import Node\n",
        "other/__init__.py": "",
        "other/a.py": "from other import b\n",
        "other/b.py": "import typing\nif typing.TYPE_CHECKING:\n    pass\nelse:\n    def f():\n        from other.a import x\n",
    }
    for name, text in files.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(text)
    assert circles(site_graph(tmp_path)) == [["other.a", "other.b"]]


def test_no_package_circle_in_the_lab():
    graphs = package_graphs(ROOT, PACKAGES)
    assert package_circles(graphs, set(KNOWN_UPWARD)) == {}
    gone = [arrow for arrow in KNOWN_UPWARD if arrow[1] not in graphs[arrow[0].rpartition(".")[0]].get(arrow[0], ())]
    assert gone == [], "these arrows are cut: take them out of KNOWN_UPWARD"


def test_the_checker_finds_a_circle_and_an_upward_import(tmp_path):
    for relative, text in {
        "sim/__init__.py": "",
        "sim/world.py": "from sim.procedures.monitor import Rules\n",
        "sim/procedures/__init__.py": "",
        "sim/procedures/monitor.py": "def f():\n    from . import report\n",
        "sim/procedures/report.py": "import sim.procedures.monitor\n",
        "sim/lonely.py": "import numpy\n",
    }.items():
        (tmp_path / relative).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / relative).write_text(text)
    graph = import_graph(tmp_path, ("sim",))
    assert graph["sim.world"] == {"sim.procedures.monitor"}
    assert graph["sim.lonely"] == set()
    assert circles(graph) == [["sim.procedures.monitor", "sim.procedures.report"]]
    graphs = package_graphs(tmp_path, ("sim",))
    assert graphs["sim"] == {"sim.world": {"sim.procedures"}, "sim.procedures": set(), "sim.lonely": set()}
    assert package_circles(graphs, set()) == {"sim.procedures": [["sim.procedures.monitor", "sim.procedures.report"]]}


def test_the_checker_finds_a_package_circle_no_module_circle_shows(tmp_path):
    for relative, text in {
        "app/__init__.py": "",
        "app/api/__init__.py": "",
        "app/api/app.py": "from app.view import view3d\n",
        "app/api/security.py": "",
        "app/view/__init__.py": "",
        "app/view/view3d.py": "def f():\n    from app.api.security import check\n",
    }.items():
        (tmp_path / relative).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / relative).write_text(text)
    assert circles(import_graph(tmp_path, ("app",))) == []  # module by module, it reads one way
    graphs = package_graphs(tmp_path, ("app",))
    assert package_circles(graphs, set()) == {"app": [["app.api", "app.view"]]}
    assert package_circles(graphs, {("app.view", "app.api")}) == {}


def test_the_checker_finds_the_client_and_the_server_importing_each_other(tmp_path):
    for relative, text in {
        "rosclient/__init__.py": "",
        "rosclient/connection.py": "from interfaces.messages import Message\n",
        "rosclient/site/rospy/__init__.py": "from .topics import Publisher\n",
        "rosclient/site/rospy/topics.py": "def f():\n    from app.ros.names import absolute\n",
        "app/__init__.py": "",
        "app/lab/__init__.py": "",
        "app/lab/lab.py": "import rospy\n",
        "app/cli/__init__.py": "",
        "app/cli/main.py": "from rosclient import run\n",
        "app/grading/__init__.py": "",
        "app/grading/services.py": "from rosclient.connection import Connection\n",
        "interfaces/__init__.py": "",
        "interfaces/messages.py": "import json\n",
    }.items():
        (tmp_path / relative).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / relative).write_text(text)
    client, server = client_imports(tmp_path, tmp_path / "rosclient" / "site")
    assert client == {"rosclient.site.rospy.topics": ["app.ros.names", "app.ros.names.absolute"]}
    assert server == {
        "app.lab.lab": ["rospy"],
        "app.grading.services": ["rosclient.connection", "rosclient.connection.Connection"],
    }  # the commands (app.cli) may start the client
