"""Students' ROS programs (tests/ros_programs/) started with `hri-lab run` / `hri-lab launch` as a
student starts them, their output read line by line, stopped with Ctrl+C (SIGINT)."""

from __future__ import annotations

import os
import queue
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

PROGRAMS = Path(__file__).parent / "ros_programs"


class Program:
    def __init__(
        self,
        url: str | None,
        command: str,
        *args: str,
        env: dict | None = None,
        terminal: bool = False,
        sigint_ignored: bool = False,
    ) -> None:
        full_env = {k: v for k, v in os.environ.items() if k != "HRI_LAB_URL"}
        full_env.update(env or {})
        url_args = ["--url", url] if url else []
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "app.cli", command, *url_args, *args],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            env=full_env,
            cwd=Path(__file__).parent.parent,
            start_new_session=terminal,
            # as a background job of a script, or a parent that ignores Ctrl+C, starts it
            preexec_fn=(lambda: signal.signal(signal.SIGINT, signal.SIG_IGN)) if sigint_ignored else None,
        )
        self.terminal = terminal  # in a process group of its own, as a terminal's foreground job
        self.lines: list[str] = []
        self._new: queue.Queue = queue.Queue()
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        for line in self.proc.stdout:
            self.lines.append(line.rstrip("\n"))
            self._new.put(line)
        self._new.put(None)

    @property
    def output(self) -> str:
        return "\n".join(self.lines)

    def wait_for_line(self, text: str, timeout: float = 60.0) -> str:
        """The first line containing `text` (AssertionError with the output when none came: a bound
        for a hung test, generous for a loaded machine)."""
        end = time.monotonic() + timeout
        seen = 0
        while time.monotonic() < end:
            for line in self.lines[seen:]:
                if text in line:
                    return line
            seen = len(self.lines)
            try:
                if self._new.get(timeout=0.1) is None and not any(text in x for x in self.lines[seen:]):  # noqa: SIM102 - two conditions kept apart, each with its own comment
                    if self.proc.poll() is not None and seen == len(self.lines):
                        break
            except queue.Empty:
                pass
        raise AssertionError(f"no line with {text!r} from the program; its output:\n{self.output}")

    def wait(self, timeout: float = 60.0) -> int:
        code = self.proc.wait(timeout=timeout)
        self._reader.join(timeout=10)  # the rest of its output
        return code

    def interrupt(self, timeout: float = 30.0) -> int:
        """Ctrl+C, as a terminal sends it (to the whole foreground group when it has one); the exit status."""
        if self.proc.poll() is None:
            if self.terminal:
                os.killpg(self.proc.pid, signal.SIGINT)
            else:
                self.proc.send_signal(signal.SIGINT)
        try:
            return self.wait(timeout)
        except subprocess.TimeoutExpired:
            self.stop()
            raise

    def stop(self) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()


def run(url: str, program: str, *args: str, **kwargs) -> Program:
    return Program(url, "run", str(PROGRAMS / program), *args, **kwargs)
