"""`hri-lab launch FILE [name:=value ...]`: roslaunch XML and ROS 2 XML launch files.

Read: <launch>, <arg name default|value> (and ROS 2's <let>), <node pkg type|exec name args output
ns|namespace> with <param name value|type> and <rosparam> inside or at the top, <include file> of a
sibling file (with its own <arg>s), the substitutions $(arg x)/$(var x), $(env X), $(optenv X d),
$(find pkg)/$(find-pkg-share pkg) and $(dirname). A node's program is its `type`/`exec` file,
looked for beside the launch file (FILE, FILE.py, PKG/FILE, PKG/scripts/FILE, scripts/FILE), then
anywhere in its package as roslaunch finds it (nodes/, src/PKG/, ...) or as a console_scripts entry
point of its setup.py (a ROS 2 package's `exec`); <remap from to> inside a node is passed to it
(`from:=to` for rospy, `-r from:=to` for rclpy). A YAML launch file (ROS 2's) is read as its XML twin.
`hri-lab launch PKG FILE` finds FILE in the package, as `ros2 launch` / `roslaunch` do; a Python
launch file (FILE.launch.py) is run by rosclient/pylaunch.py.

The lab is started first (`hri-lab serve` on a free port) unless --url is given; every node runs as
`hri-lab run` runs it (rosclient/boot.py), its parameters passed the way its API reads them:
ROS 1 files as `_name:=value` and `__name:=NAME` (rospy), ROS 2 files as `--ros-args -r __node:=NAME
-p name:=value` (rclpy); top-level <param>/<rosparam> go to the lab's parameter server. Ctrl+C
stops every node (SIGINT, then SIGKILL after a grace period) and the lab; a node that ends is
reported by name with its exit status, as roslaunch reports it.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import re
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import xml.etree.ElementTree as ET
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

from rosclient import packages
from rosclient.run import command, program_env

GRACE = 10.0  # s a node has to end after Ctrl+C before it is killed
MAX_INCLUDES = 16  # <include>s within <include>s (a file that includes itself is refused at once)
NODE_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")  # a ROS graph resource's base name (no namespace, no path)


class LaunchError(Exception):
    """A launch file that cannot be read: names the file and what is wrong."""


@dataclass
class NodeSpec:
    name: str
    program: Path
    args: list[str]
    params: dict[str, Any] = field(default_factory=dict)
    output: str = "log"
    namespace: str = "/"
    ros2: bool = False
    remaps: list[tuple[str, str]] = field(default_factory=list)
    entry: str | None = None  # a console_scripts entry point (rosclient/executables.py)

    def argv(self) -> list[str]:
        extra = [a for a in self.args]
        if self.ros2:
            ros_args = ["-r", f"__node:={self.name}"]
            if self.namespace.strip("/"):
                ros_args += ["-r", f"__ns:={self.namespace}"]
            for key, value in self.params.items():
                ros_args += ["-p", f"{key}:={_text(value)}"]
            for source, target in self.remaps:
                ros_args += ["-r", f"{source}:={target}"]
            return [*extra, "--ros-args", *ros_args]
        namespace = [f"__ns:={self.namespace}"] if self.namespace.strip("/") else []  # roslaunch's <group ns>
        remaps = [f"{source}:={target}" for source, target in self.remaps]
        params = (f"_{k}:={_text(v)}" for k, v in self.params.items())
        return [*extra, *remaps, f"__name:={self.name}", *namespace, *params]


@dataclass
class Launch:
    nodes: list[NodeSpec] = field(default_factory=list)
    params: dict[str, Any] = field(default_factory=dict)  # global name -> value (ROS 1 parameter server)


def _text(value: Any) -> str:
    return value if isinstance(value, str) else json.dumps(value)


_SUB = re.compile(r"\$\((\S+)(?:\s+([^)]*))?\)")


class Reader:
    def __init__(self, path: Path, args: dict[str, str], including: tuple[Path, ...] = ()) -> None:
        self.path = path.resolve()
        self.args = dict(args)
        self.launch = Launch()
        self.including = including  # the files whose <include> led here, outermost first
        self.at: Any = None  # the element being read (lxml's, with its sourceline): where a refusal points

    def fail(self, what: str) -> LaunchError:
        line = getattr(self.at, "sourceline", None)
        return LaunchError(f"{self.path}{f', line {line}' if line else ''}: {what}")

    def sub(self, text: str | None) -> str:
        if text is None:
            return ""

        def replace(m: re.Match) -> str:
            kind, rest = m.group(1), (m.group(2) or "").strip()
            if kind in ("arg", "var"):
                if rest not in self.args:
                    raise self.fail(
                        f"$({kind} {rest}): no argument '{rest}' (declare it with <arg name=\"{rest}\" "
                        f'default="..."/> or pass {rest}:=VALUE)'
                    )
                return self.args[rest]
            if kind == "env":
                if rest not in os.environ:
                    raise self.fail(f"$(env {rest}): environment variable {rest} is not set")
                return os.environ[rest]
            if kind == "optenv":
                name, _, default = rest.partition(" ")
                return os.environ.get(name, default)
            if kind in ("find", "find-pkg-share", "find-pkg-prefix"):
                return str(self.package_dir(rest))
            if kind == "dirname":
                return str(self.path.parent)
            raise self.fail(f"unsupported substitution $({kind} ...)")

        return _SUB.sub(replace, text)

    def package_dir(self, package: str) -> Path:
        named = packages.find(packages.workspace_of(self.path, os.environ.get("HRI_LAB_WORKSPACE") or None))
        if package in named:  # by its package.xml name (rosclient/packages.py)
            return named[package]
        for folder in [self.path.parent, *self.path.parents]:
            if folder.name == package:
                return folder
            if (folder / package).is_dir():
                return folder / package
        return self.path.parent

    def read(self) -> Launch:
        if self.path.suffix in (".yaml", ".yml"):
            return self.read_yaml()
        from lxml import etree  # each element's line; libxml2's depth limit (256) and no entity expansion

        parser = etree.XMLParser(resolve_entities=False, no_network=True, huge_tree=False)
        try:
            root = etree.parse(str(self.path), parser).getroot()
        except OSError as exc:
            raise self.fail(f"not a launch file ({exc})") from None
        except etree.XMLSyntaxError as exc:
            raise LaunchError(f"{self.path}, line {exc.lineno}: not a launch file ({exc.msg})") from None
        if root.tag != "launch":
            raise self.fail(f"the root element must be <launch>, not <{root.tag}>")
        self.element(root, "/")
        return self.launch

    def read_yaml(self) -> Launch:
        """A ROS 2 YAML launch file, read as the XML it stands for: `launch:` a list of one-key
        mappings (tag: attributes), a list inside an entry its children (`param:`, `remap:`, `arg:`)."""
        import yaml

        try:
            data = yaml.safe_load(self.path.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, yaml.YAMLError) as exc:
            raise self.fail(f"not a launch file ({exc})") from None
        if not isinstance(data, dict) or not isinstance(data.get("launch"), list):
            raise self.fail("a YAML launch file holds `launch:`, a list of its entries")
        root = ET.Element("launch")
        _yaml_children(root, data["launch"], self)
        self.element(root, "/")
        return self.launch

    def element(self, parent: ET.Element, namespace: str) -> None:
        for child in parent:
            if not isinstance(child.tag, str):
                continue
            self.at = child
            if not self.applies(child):
                continue
            tag = child.tag
            if tag == "arg":
                name = child.get("name")
                if not name:
                    raise self.fail("<arg> needs a name")
                if "value" in child.attrib:
                    self.args[name] = self.sub(child.get("value"))
                elif name not in self.args:
                    if "default" not in child.attrib:
                        raise self.fail(f"argument '{name}' has no value: pass {name}:=VALUE")
                    self.args[name] = self.sub(child.get("default"))
            elif tag == "let":
                self.args[child.get("name", "")] = self.sub(child.get("value"))
            elif tag == "node":
                self.node(child, namespace)
            elif tag == "param":
                name, value = self.param(child)
                self.launch.params[_join(namespace, name)] = value
            elif tag == "rosparam":
                for name, value in self.rosparam(child).items():
                    self.launch.params[_join(namespace, name)] = value
            elif tag == "include":
                self.include(child)
            elif tag in ("group",):
                self.element(child, _join(namespace, self.sub(child.get("ns") or child.get("namespace") or "")))
            elif tag in ("remap", "machine", "env", "set_env", "test", "push-ros-namespace"):
                continue
            else:
                raise self.fail(f"unsupported element <{tag}>")

    def applies(self, element: ET.Element) -> bool:
        if "if" in element.attrib:
            return self.sub(element.get("if")).lower() in ("1", "true")
        if "unless" in element.attrib:
            return self.sub(element.get("unless")).lower() not in ("1", "true")
        return True

    def node(self, element: ET.Element, namespace: str) -> None:
        ros2 = "exec" in element.attrib
        program_name = self.sub(element.get("exec") or element.get("type"))
        package = self.sub(element.get("pkg"))
        if not program_name:
            raise self.fail("<node> needs type= (ROS 1) or exec= (ROS 2): the program to run")
        program, entry = self.find_program(package, program_name)
        name = self.sub(element.get("name")) or Path(program_name).stem
        if not NODE_NAME.match(name):
            raise self.fail(
                f"node name {name[:100]!r} is not a ROS name: a letter, then letters, digits and '_' "
                "(a namespace goes in ns=)"
            )
        spec = NodeSpec(
            name,
            program,
            self.sub(element.get("args")).split(),
            output=element.get("output", "log"),
            namespace=_join(namespace, self.sub(element.get("ns") or element.get("namespace") or "")),
            ros2=ros2,
            entry=entry,
        )
        for child in element:
            self.at = child
            if child.tag == "remap":
                spec.remaps.append((self.sub(child.get("from")), self.sub(child.get("to"))))
            elif child.tag == "param":
                key, value = self.param(child)
                spec.params[key] = value
            elif child.tag == "rosparam":
                spec.params.update(self.rosparam(child))
        self.at = element
        self.launch.nodes.append(spec)

    def find_program(self, package: str, name: str) -> tuple[Path, str | None]:
        if "/" in name or "\\" in name or name in (".", "..") or "/" in package or package in (".", ".."):
            raise self.fail(
                f"node program {name[:100]!r} of package {package[:100]!r}: a program's file name in its package, "
                "not a path"
            )
        found = self.in_package(package, name)
        if found is not None and found[1] is not None:  # a console_scripts entry point: what ros2 run runs
            return found
        base = self.path.parent
        candidates = []
        for stem in (name, name + ".py") if not name.endswith(".py") else (name,):
            candidates += [
                base / stem,
                base / package / stem,
                base / package / "scripts" / stem,
                base / "scripts" / stem,
                self.package_dir(package) / stem,
                self.package_dir(package) / "scripts" / stem,
                self.package_dir(package) / package / stem,  # an ament_python package's module
            ]
        inside = (base.resolve(), self.package_dir(package).resolve())  # a link out of them is not the package's
        for candidate in candidates:
            if candidate.is_file() and any(candidate.resolve().is_relative_to(root) for root in inside):
                return candidate, None
        if found is not None:
            return found
        raise self.fail(
            f"node program {name!r} of package {package!r} not found (looked beside the launch file: "
            f"{', '.join(str(c) for c in candidates[:4])}, ...)"
        )

    def in_package(self, package: str, name: str) -> tuple[Path, str | None] | None:
        """The program as rosrun / ros2 run find it in the package: an entry point, or a file anywhere in it."""
        from rosclient import executables

        roots = executables.workspaces(self.path.parent, os.environ.get("HRI_LAB_WORKSPACE") or None)
        try:
            found = executables.resolve(package, name, roots)
        except executables.NotFound:
            return None
        return found.program, found.entry

    def param(self, element: ET.Element) -> tuple[str, Any]:
        from rosclient.process import parse_value

        name = self.sub(element.get("name"))
        if not name:
            raise self.fail("<param> needs a name")
        if "value" not in element.attrib:
            if "textfile" in element.attrib:
                return name, self.text_of(self.sub(element.get("textfile")), f'<param name="{name}" textfile=...>')
            raise self.fail(f'<param name="{name}"> needs a value')
        text = self.sub(element.get("value"))
        kind = element.get("type")
        if kind in ("str", "string"):
            return name, text
        try:
            if kind == "int":
                return name, int(text)
            if kind == "double":
                return name, float(text)
        except ValueError:
            raise self.fail(
                f'<param name="{name}" type="{kind}">: {text[:100]!r} is not a{"n" if kind == "int" else ""} {kind}'
            ) from None
        if kind == "bool":
            return name, text.lower() == "true"
        return name, parse_value(text)

    def rosparam(self, element: ET.Element) -> dict[str, Any]:
        import yaml

        if element.get("command", "load") != "load":
            return {}
        if element.get("file"):
            text = self.text_of(self.sub(element.get("file")), "<rosparam file=...>")
        else:
            text = self.sub(element.text or "")
        try:
            data = yaml.safe_load(text) or {}
        except yaml.YAMLError as exc:
            raise self.fail(f"<rosparam>: not YAML ({exc})") from None
        param = element.get("param")
        if param:
            return {param: data}
        if not isinstance(data, dict):
            raise self.fail("<rosparam> without param= must hold a YAML mapping")
        return data

    def text_of(self, file: str, what: str) -> str:
        """A file's text for `what`, or a refusal naming it."""
        try:
            return Path(file).read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            raise self.fail(f"{what}: cannot read {file}: {exc}") from None

    def include(self, element: ET.Element) -> None:
        target = Path(self.sub(element.get("file")))
        if not target.is_absolute():
            target = self.path.parent / target
        chain = (*self.including, self.path)
        if target.resolve() in chain:
            raise self.fail(
                f"<include> of {target.resolve()}, which is including it: a launch file that includes itself"
            )
        if len(chain) > MAX_INCLUDES:
            raise self.fail(f"<include>s nest deeper than {MAX_INCLUDES}")
        args = {}
        for child in element:
            if child.tag == "arg":
                args[child.get("name", "")] = self.sub(child.get("value"))
        inner = Reader(target, args, chain)
        included = inner.read()
        self.launch.nodes.extend(included.nodes)
        self.launch.params.update(included.params)


def _yaml_children(parent: ET.Element, entries: Any, reader: Reader) -> None:
    for entry in entries if isinstance(entries, list) else [entries]:
        if not isinstance(entry, dict) or len(entry) != 1:
            raise reader.fail(f"a YAML launch entry is a mapping of one tag, not {str(entry)[:100]!r}")
        ((tag, body),) = entry.items()
        tag = str(tag)
        if tag in ("push-ros-namespace", "push_ros_namespace"):  # the group's namespace
            parent.set("namespace", str((body or {}).get("namespace", "")))
            continue
        child = ET.SubElement(parent, tag)
        if isinstance(body, list):
            _yaml_children(child, body, reader)
            continue
        for key, value in (body or {}).items():
            if key == "children":
                _yaml_children(child, value, reader)
            elif isinstance(value, list) and all(isinstance(v, dict) for v in value):
                for item in value:
                    ET.SubElement(child, str(key), {str(k): _yaml_text(v) for k, v in item.items()})
            else:
                child.set(str(key), _yaml_text(value))


def _yaml_text(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    return value if isinstance(value, str) else json.dumps(value)


def _join(namespace: str, name: str) -> str:
    if name.startswith("/"):
        return name
    return "/" + "/".join(p for p in (namespace.strip("/"), name.strip("/")) if p)


def read(path: Path, args: dict[str, str] | None = None) -> Launch:
    return Reader(path, args or {}).read()


def read_yaml(path: Path, args: dict[str, str] | None = None) -> Launch:
    return Reader(path, args or {}).read_yaml()


# --- running ------------------------------------------------------------------------------------
class Running:
    def __init__(self, spec: NodeSpec, index: int, url: str, workspace: str | None, logs: Path) -> None:
        self.spec, self.label = spec, f"{spec.name}-{index}"
        env = program_env(url, workspace)
        root = str(Path(__file__).resolve().parents[1])
        env["PYTHONPATH"] = os.pathsep.join(p for p in (root, env.get("PYTHONPATH", "")) if p)
        self.log = logs / f"{self.label}.log"
        self.argv = command(str(spec.program), spec.argv(), spec.entry)
        self.proc = subprocess.Popen(
            self.argv, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True
        )  # Ctrl+C reaches it from here, once
        self.reported = False
        threading.Thread(target=self._relay, daemon=True).start()

    def _relay(self) -> None:
        relay_output(self.proc, self.log, self.spec.name if self.spec.output == "screen" else None)


class LabServer(Protocol):
    """A lab started for the launch file (app/cli/launch_nodes.py hands one in): its URL, its stop."""

    url: str

    def stop(self) -> None: ...


def target(args: argparse.Namespace) -> tuple[Path, dict[str, str]] | str:
    """What `hri-lab launch FILE|PKG FILE [NAME:=VALUE ...]` names: the launch file (a package's found
    as ros2 launch and roslaunch find it) and its arguments; or why not."""
    path = Path(args.file)
    items = list(args.args)
    if not path.is_file() and items and ":=" not in items[0]:  # `hri-lab launch PKG FILE`, as ros2 launch / roslaunch
        found = launch_file_of(args.file, items.pop(0), args.workspace)
        if isinstance(found, str):
            return found
        path = found
    bad = [item for item in items if ":=" not in item]
    if bad:
        return f"launch arguments are NAME:=VALUE, got {bad[0]!r}"
    return path, dict(item.split(":=", 1) for item in items)


def relay_output(proc: subprocess.Popen, log_path: Path, screen_label: str | None) -> None:
    """A launched process's output, line by line, into its log file and, with a label, to the
    screen as `[label] line` (a node's output="screen"), as roslaunch and ros2 launch relay it."""
    assert proc.stdout is not None  # started with stdout=PIPE
    with open(log_path, "w", encoding="utf-8") as log:
        for line in proc.stdout:
            log.write(line)
            log.flush()
            if screen_label is not None:
                sys.stdout.write(f"[{screen_label}] {line}")
                sys.stdout.flush()


def log_dir() -> Path:
    """A new folder for one launch's logs where ROS 2's launch makes it (launch/logging's
    `_get_logging_directory` and `_make_unique_log_dir`): below $ROS_LOG_DIR, else $ROS_HOME/log, else
    ~/.ros/log, named by the time, the host and this process, with `latest` pointing at it. Where
    that base cannot be written (a read-only home), a temporary folder."""
    base = os.environ.get("ROS_LOG_DIR") or os.path.join(os.environ.get("ROS_HOME") or "~/.ros", "log")
    base_path = Path(os.path.normpath(os.path.expanduser(base)))
    try:
        while True:
            stamp = datetime.datetime.now().strftime("%Y-%m-%d-%H-%M-%S-%f")
            folder = base_path / f"{stamp}-{socket.gethostname()}-{os.getpid()}"
            try:
                folder.mkdir(parents=True)
                break
            except FileExistsError:
                continue
    except OSError:
        return Path(tempfile.mkdtemp(prefix="hri-lab-launch-"))
    latest = base_path / "latest"
    try:
        if latest.is_symlink():
            latest.unlink()
        if not latest.exists():  # a folder of that name is the user's: left alone, as launch leaves it
            latest.symlink_to(folder, target_is_directory=True)
    except OSError:
        pass
    return folder


def stopped_by_signals() -> threading.Event:
    """Set by Ctrl+C (SIGINT) or SIGTERM: the launch then stops its nodes, as roslaunch does."""
    stopping = threading.Event()
    signal.signal(signal.SIGINT, lambda *_: stopping.set())
    signal.signal(signal.SIGTERM, lambda *_: stopping.set())
    return stopping


def lab_to_use(url: str | None, start_lab: Callable[[], LabServer] | None) -> tuple[str, LabServer | None] | None:
    """The lab a launch runs against: at `url`, or one that `start_lab` starts (the launch stops it
    after its nodes, as roslaunch its roscore); None, said on stderr, when there is neither."""
    if url is not None:
        return url, None
    if start_lab is None:
        print("error: no lab: give its address with --url", file=sys.stderr)
        return None
    print("starting the lab (hri-lab serve) ...", flush=True)
    server = start_lab()
    print(f"the lab: {server.url}", flush=True)
    return server.url, server


def run(
    args: argparse.Namespace, path: Path, launch_args: dict[str, str], start_lab: Callable[[], LabServer] | None = None
) -> int:
    """`hri-lab launch` of an XML or YAML file (`path`, with `launch_args`): its nodes against the lab
    at args.url, or against one that `start_lab` starts (stopped after the nodes, as roslaunch's roscore)."""
    try:
        launch = read(path, launch_args)
    except LaunchError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    stopping = stopped_by_signals()
    found = lab_to_use(args.url, start_lab)
    if found is None:
        return 2
    url, server = found
    logs = log_dir()
    running: list[Running] = []
    crashed = 0
    try:
        if launch.params:
            set_params(url, launch.params)
        print(f"launching {len(launch.nodes)} node(s) of {path} (logs in {logs})", flush=True)
        for index, spec in enumerate(launch.nodes, 1):
            running.append(Running(spec, index, url, args.workspace, logs))
            print(f"process[{spec.name}-{index}]: started with pid [{running[-1].proc.pid}]", flush=True)
        while not stopping.is_set() and any(r.proc.poll() is None for r in running):
            for r in running:
                code = r.proc.poll()
                if code is not None and not r.reported:
                    r.reported = True
                    if code == 0:
                        print(f"[{r.label}] process has finished cleanly", flush=True)
                    else:
                        crashed += 1
                        print(
                            f"[{r.label}] process has died [pid {r.proc.pid}, exit code {code}, cmd "
                            f"{' '.join(r.argv[3:])}]\nlog file: {r.log}",
                            flush=True,
                        )
            stopping.wait(0.1)
        if stopping.is_set():
            print("shutting down processing monitor...", flush=True)
    finally:
        _stop(running)
        if server is not None:
            server.stop()
    for r in running:  # the ones that ended while stopping
        if not r.reported and r.proc.returncode not in (0, -signal.SIGINT, 130):
            crashed += 1
            print(f"[{r.label}] process has died [pid {r.proc.pid}, exit code {r.proc.returncode}]", flush=True)
    print("done", flush=True)
    return 1 if crashed else 0


def _stop(running: list[Running]) -> None:
    """Ctrl+C to every node still running, as roslaunch sends it; killed after GRACE s."""
    for r in running:
        if r.proc.poll() is None:
            r.proc.send_signal(signal.SIGINT)
    deadline = time.monotonic() + GRACE
    for r in running:
        try:
            r.proc.wait(timeout=max(deadline - time.monotonic(), 0.1))
        except subprocess.TimeoutExpired:
            r.proc.kill()
            r.proc.wait()


def launch_file_of(package: str, name: str, workspace: str | None) -> Path | str:
    """A package's launch file by its name (its launch/ folder first, then anywhere in it), or why not."""
    from rosclient import executables

    where = executables.find_package(package, executables.workspaces(Path.cwd(), workspace))
    if where is None:
        return f"Package '{package}' not found (give its workspace with --workspace DIR)"
    if "/" in name or name in (".", ".."):
        return f"{name[:100]!r}: a launch file's name in package '{package}', not a path"
    files = executables.package_files(where[0], name)
    launch_folder = [f for f in files if f.parent.name == "launch"]
    if not files:
        return f"file '{name}' was not found in the share directory of package '{package}' at '{where[0]}'"
    return (launch_folder or files)[0]


def set_params(url: str, params: dict[str, Any]) -> None:
    from rosclient.connection import Connection

    connection = Connection(url)
    try:
        for name, value in params.items():
            connection.call_service("/rosapi/set_param", {"name": name, "value": json.dumps(value)}, timeout=10)
    finally:
        connection.closing = True
        connection.close()
