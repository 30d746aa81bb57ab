"""The commands a page of docs/ shows, run in order as a reader would (issue 32): so that a page and
the program cannot disagree.

The pages' convention (each page states it): every line of a fenced shell block is a command, run
in order in an empty folder where `.venv` and `tests` are this checkout's (a reader's checkout);
a line ending in `&` runs in the background, as in a terminal of its own, until the page ends; a
line whose comment says `(not run by the docs test: WHY)` is not run; a command ends with exit
status 0 unless its comment states `exit status N`.

What the runner does that a reader does without thinking:
- after starting a lab in the background it waits until the lab answers (/health); starting a lab
  stops the page's earlier one first (Ctrl+C in its terminal: one lab per port, as the pages say),
  after starting it once beside the earlier one, as a reader who forgot to: it must end at once
  (exit status 1) and say what to do, the `--port` for a second lab included;
- after starting any other program in the background it waits for its first line of output (a
  node's "node ready", a server's "Ready to ...", a launch's "the lab: ...") and then until the
  lab's list of services has settled (a node's advertise reaches the lab after its ready line);
- the one change it makes to a command: the lab's port 8000 becomes a free one (other labs on
  this machine may hold 8000), in `hri-lab serve`, `127.0.0.1:8000` and `--port 8000`; the clients
  find it in $HRI_LAB_URL, as a reader's find the default.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import time
from dataclasses import dataclass, field
from pathlib import Path

from app.serving.launch import free_port
from tests.http_client import http
from tests.waiting import wait_for

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
NOT_RUN = "(not run by the docs test:"
EXIT_STATUS = re.compile(r"exit status (\d+)")
SHELL_BLOCKS = ("", "sh", "bash", "shell")
COMMAND_TIMEOUT = 1800.0  # s: a bound for a hung command (a whole grade took 15 min at a load average of 28)
READY_TIMEOUT = 180.0  # s: a background program's first line, a lab's first answer


@dataclass
class Command:
    line: str  # as the page writes it
    command: str  # without its comment and its trailing `&`
    comment: str
    background: bool

    @property
    def run(self) -> bool:
        return NOT_RUN not in self.comment

    @property
    def exit_status(self) -> int:
        found = EXIT_STATUS.search(self.comment)
        return int(found.group(1)) if found else 0


def split_comment(line: str) -> tuple[str, str]:
    """(command, comment): a `#` after whitespace and outside quotes starts the comment."""
    quote = ""
    for i, char in enumerate(line):
        if quote:
            quote = "" if char == quote else quote
        elif char in "'\"":
            quote = char
        elif char == "#" and (i == 0 or line[i - 1].isspace()):
            return line[:i].rstrip(), line[i + 1 :].strip()
    return line.rstrip(), ""


def page_commands(page: str) -> list[Command]:
    """The commands of a page's fenced shell blocks, in order."""
    text = (DOCS / page).read_text(encoding="utf-8")
    found = []
    for block in re.finditer(r"^```(\w*)\n(.*?)^```", text, re.S | re.M):
        if block.group(1) not in SHELL_BLOCKS:
            continue
        for line in block.group(2).splitlines():
            if not line.strip():
                continue
            command, comment = split_comment(line)
            background = command.endswith("&") and not command.endswith("&&")
            found.append(
                Command(line, command.removesuffix("&").rstrip() if background else command, comment, background)
            )
    return found


def is_lab(command: str) -> bool:
    return re.search(r"hri-lab serve\b", command) is not None


def on_port(command: str, port: int) -> str:
    command = command.replace("127.0.0.1:8000", f"127.0.0.1:{port}").replace("--port 8000", f"--port {port}")
    if is_lab(command) and "--port" not in command:
        command = re.sub(r"hri-lab serve\b", f"hri-lab serve --port {port}", command)
    return command


@dataclass
class Background:
    command: Command
    process: subprocess.Popen
    log: Path
    with_lab: bool  # ends with the page's lab (a program connected to it, or the lab itself)
    stopped: bool = False
    kept: str = ""  # its output once its log is gone

    def output(self) -> str:
        return self.log.read_text(encoding="utf-8", errors="replace") if self.log.exists() else self.kept


@dataclass
class PageRun:
    """One page's commands run in `folder`, its labs on `port`."""

    folder: Path
    port: int = field(default_factory=free_port)
    background: list[Background] = field(default_factory=list)
    transcript: list[str] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.folder.mkdir(parents=True)
        for name in (".venv", "tests"):
            (self.folder / name).symlink_to(ROOT / name)
        self.url = f"http://127.0.0.1:{self.port}"
        env = {k: v for k, v in os.environ.items() if k not in ("HRI_LAB_GRADE_SEED", "HRI_LAB_TOKEN")}
        self.env = env | {
            "PATH": f"{ROOT / '.venv' / 'bin'}:{env.get('PATH', '')}",
            "HRI_LAB_URL": self.url,
            "HRI_LAB_VIEW": "none",  # the 3D view's port is not the page's concern
            "PYTHONUNBUFFERED": "1",
        }

    def lab_running(self) -> bool:
        return any(b.with_lab and is_lab(b.command.command) and not b.stopped for b in self.background)

    def __call__(self, command: Command) -> None:
        if not command.run:
            self.transcript.append(f"(not run) {command.line}")
            return
        text = on_port(command.command, self.port)
        self.transcript.append(f"$ {text}{' &' if command.background else ''}")
        if command.background:
            self._start(command, text)
            return
        done = subprocess.run(
            ["bash", "-c", text],
            cwd=self.folder,
            env=self.env,
            capture_output=True,
            text=True,
            timeout=COMMAND_TIMEOUT,
            stdin=subprocess.DEVNULL,
        )
        self.transcript.append((done.stdout + done.stderr)[-3000:])
        assert done.returncode == command.exit_status, self.story(
            f"`{command.line}` ended with exit status {done.returncode}, the page says {command.exit_status}"
        )
        assert "Traceback (most recent call last)" not in done.stderr, self.story(f"`{command.line}` crashed")

    def _beside(self, command: Command, text: str) -> None:
        """The lab started while the page's earlier one holds the port (the reader forgot Ctrl+C):
        it ends at once, saying to stop the other or to take the next free port."""
        done = subprocess.run(
            ["bash", "-c", f"exec {text}"],
            cwd=self.folder,
            env=self.env,
            capture_output=True,
            text=True,
            timeout=READY_TIMEOUT,
            stdin=subprocess.DEVNULL,
        )
        said = done.stdout + done.stderr
        self.transcript.append(f"$ {text} &   # beside the running lab\n{said[-3000:]}")
        assert done.returncode == 1, self.story(
            f"`{command.line}` beside the running lab: exit status {done.returncode}"
        )
        assert "One lab per port" in said and "Ctrl+C" in said, self.story(f"`{command.line}` beside a lab: {said}")
        assert re.search(rf"--port (?!{self.port}\b)\d+ \(its clients: --url", said), self.story(said)
        assert "Traceback (most recent call last)" not in said, self.story(f"`{command.line}` crashed")

    def _start(self, command: Command, text: str) -> None:
        lab = is_lab(text)
        if lab and self.lab_running() and f"--port {self.port}" in text:
            self._beside(command, text)
        if lab:  # Ctrl+C in the terminal of the page's earlier lab: its programs go with it
            for earlier in self.background:
                if earlier.with_lab and not earlier.stopped:
                    self._stop(earlier)
        log = self.folder.parent / f"{self.folder.name}-background-{len(self.background)}.log"
        with open(log, "w") as out:
            process = subprocess.Popen(
                ["bash", "-c", f"exec {text}"],
                cwd=self.folder,
                env=self.env,
                stdout=out,
                stderr=subprocess.STDOUT,
                stdin=subprocess.DEVNULL,
                start_new_session=True,
            )
        own_lab = re.search(r"hri-lab launch\b", text) is not None and "--url" not in text  # launch starts its own
        started = Background(command, process, log, with_lab=not own_lab)
        self.background.append(started)

        def ready() -> bool:
            assert process.poll() is None, self.story(f"`{command.line}` ended:\n{started.output()}")
            if lab:
                try:
                    return http.get(f"{self.url}/health", timeout=5).status_code == 200
                except Exception:  # noqa: BLE001 - not listening yet
                    return False
            return started.output().strip() != ""

        wait_for(ready, READY_TIMEOUT)
        if not lab and self.lab_running():
            self._settled()

    def _settled(self) -> None:
        """Until the lab's list of services (and who provides each) is the same twice, 1 s apart."""
        last: list = []

        def same() -> bool:
            nonlocal last
            now = http.get(f"{self.url}/services", timeout=10).json()
            if now == last:
                return True
            last = now
            time.sleep(1.0)
            return False

        wait_for(same, 30.0)

    def _stop(self, entry: Background) -> None:
        entry.stopped = True
        for signum, grace in ((signal.SIGINT, 20.0), (signal.SIGKILL, 10.0)):
            try:
                os.killpg(entry.process.pid, signum)
            except ProcessLookupError:
                pass
            try:
                entry.process.wait(timeout=grace)
                break
            except subprocess.TimeoutExpired:
                continue

    def finish(self) -> None:
        """Every background program the page left running was still running (none ended on its
        own; those of a lab the page replaced aside); then all are stopped."""
        try:
            for entry in self.background:
                if not entry.stopped:
                    assert entry.process.poll() is None, self.story(
                        f"`{entry.command.line}` ended on its own:\n{entry.output()[-3000:]}"
                    )
        finally:
            for entry in self.background:
                if entry.process.poll() is None:
                    self._stop(entry)
                entry.kept = entry.output()
                entry.log.unlink(missing_ok=True)

    def story(self, what: str) -> str:
        """What went wrong, after the page's commands so far and their output."""
        tail = "\n".join(self.transcript[-30:])
        logs = "\n".join(f"--- {b.command.line}\n{b.output()[-1500:]}" for b in self.background)
        return f"{what}\n\n{tail}\n\n{logs}"


def run_page(page: str, folder: Path) -> PageRun:
    """Every command of `page`, in order, in `folder`; what ran (the transcript) is returned."""
    commands = page_commands(page)
    assert commands, f"{page} shows no command"
    run = PageRun(folder)
    try:
        for command in commands:
            run(command)
        for entry in run.background:  # the output a reader sees before closing the terminals
            output = entry.output()
            assert "Traceback (most recent call last)" not in output, run.story(f"`{entry.command.line}` crashed")
            assert "TypeError" not in output, run.story(f"`{entry.command.line}` logged a TypeError")
    finally:
        run.finish()
    return run
