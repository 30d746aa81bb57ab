"""Public ROS programs nobody here wrote, run unchanged against the lab (issue 31, item 8): each
program of the manifest (bench/ros_corpus.toml) under `hri-lab run` (a launch file under `hri-lab
launch`), or as its docs start it (`hri-lab run PKG EXE`, `hri-lab launch PKG FILE`: the checkout is
the workspace, as after sourcing its setup file), with its partner where it needs one (a talker with its listener, a server with its
client), against one `hri-lab serve --exercises` started here on a free port; pass or fail per
program with the reason, then the pass rate.

The programs are not part of this repository: fetch their repositories and unpack the folders the
manifest names into `DIR/OWNER+NAME@COMMIT/` (COMMIT: the commit's first 12 hex digits or more),
e.g. `/work/corpus/ros2+examples@4a4082a8db04/rclpy/...`; a DIR argument is either such a folder
or a folder holding them. docs/ros-programs.md lists the corpus and the figures.

    .venv/bin/python -m bench.ros_corpus /work/corpus                     # this checkout's lab
    .venv/bin/python -m bench.ros_corpus --lab /work/wt/i31-rclpy /work/corpus   # another one's
    .venv/bin/python -m bench.ros_corpus /work/corpus -k listener --verbose    # some, with output

`--lab DIR` runs DIR/.venv/bin/hri-lab (its serve, run and launch), so a branch is measured with
its own code. What "pass" means for a program is the manifest's data: the lines to see in its
output or its partners', the `hri-lab` client commands whose output must match (a service call,
a parameter read), and the exit status when it ends by itself. Every wait is bounded; every
process started here (in a process group of its own) is stopped before the next program starts.
"""

from __future__ import annotations

import argparse
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
import tomllib
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

from app.serving.launch import stop_group

ROOT = Path(__file__).resolve().parent.parent
MANIFEST = Path(__file__).with_name("ros_corpus.toml")
CHECKOUT_NAME = re.compile(r"^(?P<owner>[\w.-]+)\+(?P<name>[\w.-]+)@(?P<commit>[0-9a-f]{7,40})$")
DEFAULT_TIMEOUT_S = 40.0  # a program's bound on a busy 2-core machine, not a speed figure
CHECK_EVERY_S = 1.0  # how often a client command that has not matched yet is tried again
STOP_GRACE_S = 10.0  # from Ctrl+C to SIGKILL
SERVER_READY_S = 180.0

PROGRAM_KEYS = {
    "repo",
    "commit",
    "path",
    "client",
    "partners",
    "args",
    "launch",
    "package",
    "executable",
    "expect",
    "checks",
    "topics",
    "interrupt",
    "exit",
    "timeout",
    "why",
}
INTERRUPT_DELAY_S = 3.0  # from the line `interrupt` names to the Ctrl+C: time for its partners to subscribe
PARTNER_KEYS = {"path", "package", "executable", "args"}
EXPECT_KEYS = {"in", "line"}
CHECK_KEYS = {"hri_lab", "line"}
TOPIC_KEYS = {"name", "type"}  # and `line`, optional
CLIENTS = {"rclpy", "rospy"}


class ManifestError(ValueError):
    """The manifest is not what this bench reads: the message names the entry and the field."""


@dataclass(frozen=True)
class Expect:
    """A line (regular expression, searched) that must appear in the program's output ("program")
    or in any of its partners' ("partner")."""

    where: str
    pattern: re.Pattern[str]


@dataclass(frozen=True)
class Check:
    """An `hri-lab` client command (its arguments, `--url` added) whose output must match `pattern`;
    tried again every CHECK_EVERY_S until it does (a service not provided yet answers 404)."""

    args: tuple[str, ...]
    pattern: re.Pattern[str]


@dataclass(frozen=True)
class Heard:
    """A topic (name, ROS type) on which the bench, subscribed over rosbridge like any client (roslibpy),
    must receive a message: what `rostopic echo` would show of a program that publishes for nobody.
    With `pattern`, a message whose JSON matches it (a program's frame on /tf, which the lab's
    frames share)."""

    name: str
    type: str
    pattern: re.Pattern[str] | None = None

    def matches(self, message: dict) -> bool:
        return self.pattern is None or self.pattern.search(json.dumps(message)) is not None


@dataclass(frozen=True)
class Start:
    """How a program or a partner is started: a file of the checkout (`hri-lab run FILE`, `hri-lab
    launch FILE`), or by its package's name as its docs start it (`hri-lab run PKG EXE`: a
    console_scripts entry point or a script rosrun finds; `hri-lab launch PKG FILE`)."""

    path: str  # inside the repository: the file that stands for it (the script, the module, the launch file)
    package: str = ""
    executable: str = ""  # with `package`, unless it is a launch file
    launch: bool = False
    args: tuple[str, ...] = ()

    def command(self, folder: Path) -> list[str]:
        """`hri-lab`'s words after the verb and its --url."""
        if not self.package:
            return [str(folder / self.path), *self.args]
        return [self.package, Path(self.path).name if self.launch else self.executable, *self.args]

    def __str__(self) -> str:
        return f"{self.package} {self.executable}" if self.package and not self.launch else self.path


@dataclass(frozen=True)
class Program:
    repo: str  # owner/name
    commit: str  # the full commit
    path: str  # inside the repository
    client: str  # rclpy or rospy
    partners: tuple[Start, ...] = ()  # in the same checkout, started before the program
    args: tuple[str, ...] = ()
    launch: bool = False  # `hri-lab launch FILE` instead of `hri-lab run FILE`
    package: str = ""  # started by its package's name (Start)
    executable: str = ""
    expect: tuple[Expect, ...] = ()
    checks: tuple[Check, ...] = ()
    topics: tuple[Heard, ...] = ()
    interrupt: re.Pattern[str] | None = None  # Ctrl+C to it INTERRUPT_DELAY_S after this line (on_shutdown)
    exit: int | None = None  # the status it ends with by itself (or on `interrupt`); None: it runs until stopped
    timeout: float = DEFAULT_TIMEOUT_S
    why: str = ""  # what it exercises

    @property
    def name(self) -> str:
        return f"{self.repo}@{self.commit[:12]}:{self.path}"

    @property
    def start(self) -> Start:
        return Start(self.path, self.package, self.executable, self.launch, self.args)


def _regex(text: object, where: str, key: str = "line") -> re.Pattern[str]:
    if not isinstance(text, str) or not text:
        raise ManifestError(f"{where}: `{key}` must be a non-empty regular expression")
    try:
        return re.compile(text)
    except re.error as exc:
        raise ManifestError(f"{where}: `{key}` is no regular expression ({exc})") from None


def _strings(value: object, where: str) -> tuple[str, ...]:
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise ManifestError(f"{where} must be a list of strings")
    return tuple(value)


def _by_package(entry: dict, where: str, launch: bool) -> tuple[str, str]:
    """(package, executable) of an entry started by its package's name ("", "" if by its file)."""
    package, executable = entry.get("package", ""), entry.get("executable", "")
    if not isinstance(package, str) or not isinstance(executable, str):
        raise ManifestError(f"{where}: `package` and `executable` must be strings")
    if executable and not package:
        raise ManifestError(f"{where}: `executable` needs its `package`")
    if package and not launch and not executable:
        raise ManifestError(f"{where}: `package` needs the `executable` to run (or launch = true)")
    if package and launch and executable:
        raise ManifestError(f"{where}: a launch file has no `executable` (its file is `path`)")
    return package, executable


def _partner(item: object, where: str) -> Start:
    """A partner: a path in the checkout, or a table of path, package, executable and args."""
    if isinstance(item, str) and item:
        return Start(item)
    if not isinstance(item, dict) or set(item) - PARTNER_KEYS or not isinstance(item.get("path"), str):
        raise ManifestError(f"{where}: a path, or a table of {', '.join(sorted(PARTNER_KEYS))} (path required)")
    package, executable = _by_package(item, where, launch=False)
    return Start(item["path"], package, executable, args=_strings(item.get("args", []), f"{where}: `args`"))


def _heard(item: object, at: str) -> Heard:
    """A `topics` entry: a topic (name, type) the program's messages are heard on, and the line one must match."""
    if (
        not isinstance(item, dict)
        or set(item) - {"line"} != TOPIC_KEYS
        or not all(isinstance(v, str) and v for v in item.values())
    ):
        raise ManifestError(f"{at}: a table of name and type (strings), and line (optional)")
    return Heard(item["name"], item["type"], _regex(item["line"], at) if "line" in item else None)


def parse_program(entry: dict, index: int) -> Program:
    where = f"program {index + 1}" + (f" ({entry['path']})" if isinstance(entry.get("path"), str) else "")
    unknown = set(entry) - PROGRAM_KEYS
    if unknown:
        raise ManifestError(f"{where}: unknown field {', '.join(sorted(unknown))}")
    for key in ("repo", "commit", "path", "client"):
        if not isinstance(entry.get(key), str) or not entry[key]:
            raise ManifestError(f"{where}: `{key}` is required (a string)")
    if not re.fullmatch(r"[\w.-]+/[\w.-]+", entry["repo"]):
        raise ManifestError(f"{where}: `repo` must be owner/name")
    if not re.fullmatch(r"[0-9a-f]{40}", entry["commit"]):
        raise ManifestError(f"{where}: `commit` must be the full 40-digit commit")
    if entry["client"] not in CLIENTS:
        raise ManifestError(f"{where}: `client` must be one of {', '.join(sorted(CLIENTS))}")
    expects = []
    for j, item in enumerate(entry.get("expect", [])):
        at = f"{where}, expect {j + 1}"
        if not isinstance(item, dict) or set(item) - EXPECT_KEYS:
            raise ManifestError(f"{at}: a table of {', '.join(sorted(EXPECT_KEYS))}")
        if item.get("in", "program") not in ("program", "partner"):
            raise ManifestError(f"{at}: `in` must be program or partner")
        expects.append(Expect(item.get("in", "program"), _regex(item.get("line"), at)))
    checks = []
    for j, item in enumerate(entry.get("checks", [])):
        at = f"{where}, check {j + 1}"
        if not isinstance(item, dict) or set(item) - CHECK_KEYS:
            raise ManifestError(f"{at}: a table of {', '.join(sorted(CHECK_KEYS))}")
        checks.append(Check(_strings(item.get("hri_lab"), f"{at}: `hri_lab`"), _regex(item.get("line"), at)))
    topics = [_heard(item, f"{where}, topic {j + 1}") for j, item in enumerate(entry.get("topics", []))]
    if not isinstance(entry.get("partners", []), list):
        raise ManifestError(f"{where}: `partners` must be a list")
    partners = tuple(_partner(item, f"{where}, partner {j + 1}") for j, item in enumerate(entry.get("partners", [])))
    package, executable = _by_package(entry, where, bool(entry.get("launch", False)))
    if any(e.where == "partner" for e in expects) and not partners:
        raise ManifestError(f"{where}: an expectation in a partner's output needs `partners`")
    exit_status = entry.get("exit")
    if exit_status is not None and (not isinstance(exit_status, int) or isinstance(exit_status, bool)):
        raise ManifestError(f"{where}: `exit` must be an integer")
    interrupt = _regex(entry["interrupt"], where, "interrupt") if "interrupt" in entry else None
    if interrupt is not None and exit_status is None:
        raise ManifestError(f"{where}: `interrupt` needs the `exit` status it ends with")
    timeout = entry.get("timeout", DEFAULT_TIMEOUT_S)
    if not isinstance(timeout, int | float) or isinstance(timeout, bool) or not 0 < timeout <= 600:
        raise ManifestError(f"{where}: `timeout` must be seconds in (0, 600]")
    if not expects and not checks and not topics and exit_status is None:
        raise ManifestError(f"{where}: nothing to judge it by (expect, checks or exit)")
    return Program(
        repo=entry["repo"],
        commit=entry["commit"],
        path=entry["path"],
        client=entry["client"],
        partners=partners,
        args=_strings(entry.get("args", []), f"{where}: `args`"),
        launch=bool(entry.get("launch", False)),
        package=package,
        executable=executable,
        expect=tuple(expects),
        checks=tuple(checks),
        topics=tuple(topics),
        interrupt=interrupt,
        exit=exit_status,
        timeout=float(timeout),
        why=str(entry.get("why", "")),
    )


def parse_manifest(text: str) -> list[Program]:
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ManifestError(f"not TOML: {exc}") from None
    unknown = set(data) - {"program"}
    if unknown:
        raise ManifestError(f"unknown top-level field {', '.join(sorted(unknown))}")
    programs = [parse_program(entry, i) for i, entry in enumerate(data.get("program", []))]
    seen: set[tuple[str, str, str, tuple[str, ...]]] = set()
    for p in programs:
        key = (p.repo, p.commit, p.path, p.args)
        if key in seen:
            raise ManifestError(f"{p.name}: listed twice")
        seen.add(key)
    return programs


def load_manifest(path: Path = MANIFEST) -> list[Program]:
    return parse_manifest(path.read_text())


# ---- where the programs are -------------------------------------------------------------------


def find_checkouts(dirs: Sequence[Path]) -> dict[tuple[str, str], Path]:
    """(owner/name, commit prefix) -> folder, for each DIR named OWNER+NAME@COMMIT and each such
    folder directly inside a DIR."""
    found: dict[tuple[str, str], Path] = {}
    for d in dirs:
        for candidate in (d, *(sorted(d.iterdir()) if d.is_dir() else ())):
            m = CHECKOUT_NAME.match(candidate.name)
            if m and candidate.is_dir():
                found[(f"{m['owner']}/{m['name']}", m["commit"])] = candidate
    return found


def checkout_of(program: Program, checkouts: dict[tuple[str, str], Path]) -> Path | None:
    for (repo, prefix), folder in checkouts.items():
        if repo == program.repo and program.commit.startswith(prefix):
            return folder
    return None


# ---- judging what was seen ---------------------------------------------------------------------

LAUNCH_PREFIX = re.compile(r"^\[(?!(DEBUG|INFO|WARN|WARNING|ERROR|FATAL)\])[A-Za-z_][\w/.-]*\] ")  # `hri-lab launch`'s
ERROR_LINE = re.compile(r"(\[(ERROR|FATAL)\]|^error:|^\w+(\.\w+)*(Error|Exception)\b)", re.IGNORECASE)


def first_error_line(lines: Sequence[str]) -> str | None:
    """The line that says what went wrong: a traceback's exception line (the first unindented line
    after `Traceback (most recent call last):`), else the first line logged as an error."""
    lines = [LAUNCH_PREFIX.sub("", line, count=1) for line in lines]
    in_traceback = False
    for line in lines:
        if line.startswith("Traceback (most recent call last):"):
            in_traceback = True
        elif in_traceback and line and not line[0].isspace():
            return line.strip()
    for line in lines:
        if ERROR_LINE.search(line.strip()):
            return line.strip()
    return None


@dataclass
class Observed:
    """What a run has shown so far."""

    program: list[str] = field(default_factory=list)
    partners: list[list[str]] = field(default_factory=list)
    program_exit: int | None = None
    partner_exits: list[int | None] = field(default_factory=list)
    heard: set[str] = field(default_factory=set)  # the topics (Program.topics) a message came on
    checks_matched: int = 0  # checks run in order: how many have matched
    last_check_output: str = ""


@dataclass(frozen=True)
class Verdict:
    passed: bool
    reason: str


def _seen(expect: Expect, seen: Observed) -> bool:
    outputs = [seen.program] if expect.where == "program" else seen.partners
    return any(expect.pattern.search(line) for lines in outputs for line in lines)


def _said(lines: Sequence[str]) -> str:
    error = first_error_line(lines)
    return f": {error}" if error else ""


def judge(program: Program, seen: Observed, timed_out: bool, partner_names: Sequence[object] = ()) -> Verdict | None:
    """The verdict on what was seen, or None while it can still pass (not timed out)."""
    missing = [e for e in program.expect if not _seen(e, seen)]
    unheard = [t for t in program.topics if t.name not in seen.heard]
    checks_done = seen.checks_matched >= len(program.checks) and not unheard
    if seen.program_exit is not None:
        if program.exit is not None and seen.program_exit != program.exit:
            return Verdict(False, f"exited with status {seen.program_exit}{_said(seen.program)}")
        own = [e for e in missing if e.where == "program"]
        if own or (program.exit is None and (missing or not checks_done)):
            wanted = _wanted(program, own or missing, seen)
            return Verdict(False, f"ended (status {seen.program_exit}) before {wanted}{_said(seen.program)}")
    for i, status in enumerate(seen.partner_exits):
        if status not in (None, 0):
            who = partner_names[i] if i < len(partner_names) else f"partner {i + 1}"
            return Verdict(False, f"partner {who} exited with status {status}{_said(seen.partners[i])}")
    if not missing and checks_done and (program.exit is None or seen.program_exit == program.exit):
        return Verdict(True, "")
    if not timed_out:
        return None
    said = _said(seen.program) or _said([line for lines in seen.partners for line in lines])
    if missing or not checks_done:
        return Verdict(False, f"waited {program.timeout:g} s for {_wanted(program, missing, seen)}{said}")
    return Verdict(False, f"did not end within {program.timeout:g} s{said}")


def _wanted(program: Program, missing: Sequence[Expect], seen: Observed) -> str:
    """What was still awaited: the first missing line, else the check that has not matched."""
    if missing:
        return f"a line /{missing[0].pattern.pattern}/ from the {missing[0].where}"
    unheard = [t for t in program.topics if t.name not in seen.heard]
    if unheard:
        pattern = f" matching /{unheard[0].pattern.pattern}/" if unheard[0].pattern else ""
        return f"a message on {unheard[0].name} ({unheard[0].type}){pattern}"
    check = program.checks[seen.checks_matched]
    last = seen.last_check_output.strip().splitlines()
    return f"`hri-lab {' '.join(check.args)}` printing /{check.pattern.pattern}/" + (
        f" (last: {last[-1][:160]})" if last else ""
    )


# ---- running ---------------------------------------------------------------------------------


class Lab:
    """A checkout of the lab: its `hri-lab` command."""

    def __init__(self, checkout: Path) -> None:
        self.checkout = checkout.resolve()
        self.command = self.checkout / ".venv" / "bin" / "hri-lab"
        if not self.command.is_file():
            raise SystemExit(f"{self.command}: missing (run `make .venv/.installed` in {self.checkout})")


class Process:
    """A command in a process group of its own, its output (stdout and stderr) read into lines."""

    def __init__(self, args: Sequence[str], cwd: Path, env: dict[str, str] | None = None) -> None:
        self.lines: list[str] = []
        self.proc = subprocess.Popen(
            list(args),
            cwd=cwd,
            env=env,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            errors="replace",
            start_new_session=True,
        )
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            self.lines.append(line.rstrip("\n"))

    def status(self) -> int | None:
        return self.proc.poll()

    def stop(self) -> None:
        """Ctrl+C to its group (as a terminal sends it), then SIGKILL after STOP_GRACE_S."""
        stop_group(self.proc, STOP_GRACE_S)
        self.proc.wait()
        self._reader.join(timeout=5)


@contextmanager
def serving(lab: Lab, work: Path, port: int | None = None) -> Iterator[str]:
    """`hri-lab serve --exercises` of `lab` on `port` (default: a free one), its outputs in `work`:
    its URL. --exercises leaves /add_two_ints and the handout's other services to the programs."""
    if port is None:
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
    output = work / "serve-output"
    output.mkdir()
    server = Process(
        [str(lab.command), "serve", "--port", str(port), "--view", "none", "--exercises", "--output-dir", str(output)],
        cwd=work,
    )
    try:
        deadline = time.monotonic() + SERVER_READY_S
        while not any("Press Ctrl+C" in line for line in server.lines):
            if server.status() is not None or time.monotonic() > deadline:
                raise SystemExit("hri-lab serve did not start:\n" + "\n".join(server.lines[-20:]))
            time.sleep(0.1)
        yield f"http://127.0.0.1:{port}"
    finally:
        server.stop()


def run_program(lab: Lab, url: str, program: Program, folder: Path, work: Path, verbose: bool = False) -> Verdict:
    # the checkout is the workspace, as a workspace is once its setup file is sourced
    env = dict(os.environ, HRI_LAB_URL=url, PYTHONUNBUFFERED="1", HRI_LAB_WORKSPACE=str(folder))
    env.pop("PYTHONPATH", None)

    def start(what: Start) -> Process:
        verb = ["launch", "--url", url] if what.launch else ["run", "--url", url]
        # by its package's name: from the workspace's root, where a student types `ros2 run` (and
        # where a README's relative paths, a params file's, start)
        return Process([str(lab.command), *verb, *what.command(folder)], cwd=folder if what.package else work, env=env)

    for what in (program.start, *program.partners):
        if not (folder / what.path).is_file():
            return Verdict(False, f"not in the corpus folder: {folder / what.path}")
    partners: list[Process] = []
    main: Process | None = None
    seen = Observed()
    listening = listen(url, program.topics, seen.heard)
    try:
        partners = [start(p) for p in program.partners]
        main = start(program.start)
        deadline = time.monotonic() + program.timeout
        next_check = 0.0
        interrupt_at: float | None = None
        while True:
            if (
                program.interrupt is not None
                and interrupt_at is None
                and any(map(program.interrupt.search, main.lines))
            ):
                interrupt_at = time.monotonic() + INTERRUPT_DELAY_S
            if interrupt_at is not None and time.monotonic() >= interrupt_at and main.status() is None:
                os.killpg(main.proc.pid, signal.SIGINT)
                interrupt_at = float("inf")
            seen.program = list(main.lines)
            seen.partners = [list(p.lines) for p in partners]
            seen.program_exit = main.status()
            seen.partner_exits = [p.status() for p in partners]
            if seen.checks_matched < len(program.checks) and time.monotonic() >= next_check:
                check = program.checks[seen.checks_matched]
                seen.last_check_output = client_command(lab, url, check.args, env)
                if check.pattern.search(seen.last_check_output):
                    seen.checks_matched += 1
                    continue
                next_check = time.monotonic() + CHECK_EVERY_S
            verdict = judge(program, seen, time.monotonic() > deadline, program.partners)
            if verdict is not None:
                return verdict
            time.sleep(0.1)
    finally:
        if listening is not None:
            listening.close()
        for proc in (main, *partners):
            if proc is not None:
                proc.stop()
        if verbose:
            for name, proc in ((program.start, main), *zip(program.partners, partners, strict=False)):
                if proc is not None:
                    print(f"    --- {name}")
                    for line in proc.lines[-40:]:
                        print(f"    | {line}")


def listen(url: str, topics: Sequence[Heard], heard: set[str]):  # -> roslibpy.Ros | None
    """Subscribed to `topics` over the lab's rosbridge endpoint with roslibpy: each name goes into
    `heard` when its first message (that matches the topic's pattern, if it has one) comes."""
    if not topics:
        return None
    import roslibpy

    host, port = url.removeprefix("http://").rsplit(":", 1)
    ros = roslibpy.Ros(host, int(port))
    ros.run(timeout=30)

    def arrived(message: dict, t: Heard) -> None:
        if t.matches(message):
            heard.add(t.name)

    for t in topics:
        roslibpy.Topic(ros, t.name, t.type).subscribe(lambda message, t=t: arrived(message, t))
    return ros


def client_command(lab: Lab, url: str, args: Sequence[str], env: dict[str, str]) -> str:
    try:
        done = subprocess.run(
            [str(lab.command), *args, "--url", url],
            capture_output=True,
            text=True,
            timeout=30,
            env=env,
            stdin=subprocess.DEVNULL,
        )
    except subprocess.TimeoutExpired:
        return "(no answer within 30 s)"
    return done.stdout + done.stderr


def stop_on_sigterm() -> None:
    """SIGTERM (`kill`, `timeout`) ends the bench as Ctrl+C does: through its `finally`s, which stop
    the lab and the programs it started (they run in process groups of their own, out of reach of
    a signal sent to the bench's group) and remove its temporary folder."""

    def terminate(signum: int, frame: object) -> None:
        raise SystemExit(128 + signum)

    signal.signal(signal.SIGTERM, terminate)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("dirs", nargs="+", type=Path, metavar="DIR", help="corpus folders (OWNER+NAME@COMMIT)")
    parser.add_argument("--lab", type=Path, default=ROOT, help="the lab's checkout (its .venv/bin/hri-lab)")
    parser.add_argument("--manifest", type=Path, default=MANIFEST)
    parser.add_argument("-k", dest="select", help="only programs whose name contains this")
    parser.add_argument("--client", choices=sorted(CLIENTS), help="only rclpy or rospy programs")
    parser.add_argument("--verbose", action="store_true", help="print each program's last output lines")
    parser.add_argument("--report", type=Path, metavar="FILE.md", help="also write the results as a Markdown table")
    args = parser.parse_args(argv)
    stop_on_sigterm()
    lab = Lab(args.lab)
    programs = load_manifest(args.manifest)
    if args.select:
        programs = [p for p in programs if args.select in p.name]
    if args.client:
        programs = [p for p in programs if p.client == args.client]
    checkouts = find_checkouts(args.dirs)
    results: list[tuple[Program, Verdict]] = []
    absent = [p for p in programs if checkout_of(p, checkouts) is None]
    for p in absent:
        print(
            f"SKIP {p.name}: no {p.repo.replace('/', '+')}@{p.commit[:12]} folder in {', '.join(map(str, args.dirs))}"
        )
    present = [p for p in programs if p not in absent]
    if not present:
        print("no program of the manifest found", file=sys.stderr)
        return 1
    print(f"lab: {lab.checkout}; {len(present)} programs")
    with tempfile.TemporaryDirectory(prefix="ros-corpus-") as tmp:
        work = Path(tmp)
        with serving(lab, work) as url:
            for p in present:
                folder = checkout_of(p, checkouts)
                assert folder is not None
                verdict = run_program(lab, url, p, folder, work, args.verbose)
                results.append((p, verdict))
                print(
                    f"{'PASS' if verdict.passed else 'FAIL'} {p.name}"
                    + ("" if verdict.passed else f": {short(verdict.reason)}"),
                    flush=True,
                )
    print(summary(results))
    if args.report:
        command = " ".join(["python -m bench.ros_corpus", *(sys.argv[1:] if argv is None else argv)])
        args.report.write_text(report(results, lab_commit(lab), command, os.getloadavg()))
    return 0


def report(results: Sequence[tuple[Program, Verdict]], lab: str, command: str, load: Sequence[float]) -> str:
    """The results as Markdown: the pass rate, then one row a program (its repository and commit, its
    path, what it exercises, the verdict and the reason), failures first."""
    lines = [
        "# Public ROS programs, unchanged: the results",
        "",
        "Written by bench/ros_corpus.py (`--report`); the corpus, the bench and how to run it:",
        "[the lab as a ROS system](ros-programs.md#measured-public-ros-programs-unchanged).",
        "",
        f"Measured {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} with `{command}`",
        f"(lab: {lab}) on the shared 2-core machine, load average {load[0]:.1f} {load[1]:.1f} {load[2]:.1f}",
        "(other developers' work running at the same time).",
        "",
        *(f"- {line}" for line in summary(results).splitlines()),
        "",
        "| repository@commit | program | what it exercises | result |",
        "|---|---|---|---|",
    ]
    for p, v in sorted(results, key=lambda r: r[1].passed):
        result = "pass" if v.passed else "**fail**: " + short(v.reason).replace("|", "\\|")
        started = (
            f" (`hri-lab {'launch' if p.launch else 'run'} {p.package} {p.start.command(Path())[1]}`)"
            if p.package
            else ""
        )
        lines.append(f"| {p.repo}@{p.commit[:12]} | `{p.path}`{started} | {p.why.replace('|', '/')} | {result} |")
    return "\n".join(lines) + "\n"


def lab_commit(lab: Lab) -> str:
    done = subprocess.run(
        ["git", "-C", str(lab.checkout), "log", "-1", "--format=%h (%s)"], capture_output=True, text=True, check=False
    )
    branch = subprocess.run(
        ["git", "-C", str(lab.checkout), "branch", "--show-current"], capture_output=True, text=True, check=False
    )
    return f"{branch.stdout.strip() or '?'} {done.stdout.strip()[:80]}"


def short(reason: str, limit: int = 300) -> str:
    return reason if len(reason) <= limit else reason[: limit - 3] + "..."


def summary(results: Sequence[tuple[Program, Verdict]]) -> str:
    lines = []
    for client in sorted(CLIENTS):
        mine = [v for p, v in results if p.client == client]
        if mine:
            lines.append(f"{client}: {sum(v.passed for v in mine)} of {len(mine)} pass")
    passed = sum(v.passed for _, v in results)
    share = 100.0 * passed / len(results) if results else 0.0
    lines.append(f"pass rate: {passed} of {len(results)} ({share:.0f} %)")
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())
