"""Where the test suite's time goes: each test file's wall time (its tests' setup, call and teardown,
as pytest reports them) and its CPU time (the worker's own and its children's: the servers, nodes,
sandboxes and browsers it started; `own s` the worker's own alone), the longest first. CPU seconds are what a shared machine is
short of; wall seconds are what a worker waits.

    .venv/bin/python -m pytest -q -n 3 --dist loadfile --no-loadscope-reorder -p bench.suite_time [FILES]
    HRI_LAB_SUITE_TIME=times.json ...   # the table as JSON too
    HRI_LAB_SUITE_PROGRAMS=1 ...        # and a second table: CPU by program (labs, browsers, grades, ...)
    HRI_LAB_SUITE_CORES=1 ...           # and the machine's cores: how busy, each CORE_WINDOW_S; when each worker ended

A pytest plugin (`-p bench.suite_time`), with or without xdist: each worker measures its tests and
hands the figures to the controller in the tests' reports; the table is printed at the end.

The file table counts a child's CPU only once the worker has waited for it. The program table
counts every descendant of the run, whoever waits for it (a sandbox's process, a browser's GPU
process, a lab's simulation process): the run's process tree sampled every `SAMPLE_PERIOD_S`
(psutil), each process's last CPU reading summed by the kind of program it is (`program_kind`). A
process shorter than a period may be missed; those are a small part of the whole. The cores' line
(`HRI_LAB_SUITE_CORES`): the machine's busy share of its CPU time, read from /proc/stat every
CORE_PERIOD_S, as the mean of each CORE_WINDOW_S, and when each worker's last test ended: whether a
run is bound by its CPU (busy throughout) or by its waits and its order (cores idle while a worker
still runs).
"""

from __future__ import annotations

import json
import os
import re
import resource
import threading
import time
from collections import Counter
from pathlib import Path

import psutil
import pytest

from sim.controllers.sandbox.watch import stat_ticks  # the one rule of what counts as busy

KEY = "suite_time_cpu_s"
OWN_KEY = "suite_time_own_cpu_s"  # the worker's own, without its children
SAMPLE_PERIOD_S = 0.25  # s between two readings of the run's process tree (the program table)
CORE_PERIOD_S = 1.0  # s between two readings of /proc/stat (the cores' line)
CORE_WINDOW_S = 20.0  # s of the run each figure of the cores' line is the mean of

# (kind, pattern of the command line), the first match names a process; forks keep their parent's
# command line (a lab's simulation process is a `hri-lab serve`)
PROGRAM_KINDS = (
    ("chromium", re.compile(r"chrom(e|ium)")),
    ("sandboxed controller", re.compile(r"sim\.controllers\.sandbox")),
    ("student program (hri-lab run)", re.compile(r"rosclient\.boot|hri-lab run\b|app\.cli run\b")),
    ("Gradescope set-up", re.compile(r"compileall|ensurepip|\buv\b|\bpip\b|setup\.sh")),
    ("Jupyter", re.compile(r"jupyter|configurable-http-proxy")),
    ("ROS 1 (Debian)", re.compile(r"/usr/bin/ros|rosmaster")),
    ("Gradescope run (run_autograder)", re.compile(r"app\.grading\.gradescope")),
    ("similarity report (copydetect)", re.compile(r"app\.grading\.similarity")),
    # pytest's own processes (not a program whose arguments name a folder of pytest's tmp_path)
    ("pytest worker", re.compile(r"exec\(eval\(sys\.stdin|-m ?pytest\b|/pytest(?:\s|$)")),
    ("multiprocessing's spawned child", re.compile(r"multiprocessing\.spawn")),
    ("hri-lab serve", re.compile(r"tests\.lab_zygote")),  # the tests' zygote, and the labs forked from it
)
LAB_CHILDREN = ("hri-lab-sim", "hri-lab-camera")
ZYGOTE = PROGRAM_KINDS[-1][1]  # its forks take their command's name (tests/lab_zygote.py)
CLI = re.compile(r"(?:hri-lab|app\.cli) ([a-z][a-z0-9-]*)")


def program_kind(cmdline: list[str], name: str = "") -> str:
    """What a process of the run is, from its command line: `hri-lab COMMAND` by its command (a lab
    is `hri-lab serve`), else one of PROGRAM_KINDS, else its program's name. A lab's forked
    children keep its command line and tell apart by their process `name`: "hri-lab-sim" (the
    simulation's loop) and "hri-lab-camera" (app/runtime/process.py, name_this_process), counted
    apart with the program that forked them (a lab, or a worker's in-process lab). A command forked
    from the tests' zygote (a lab, a grade) keeps the zygote's command line and takes its command
    as its name ("grade")."""
    if name in LAB_CHILDREN:
        return f"{name} ({program_kind(cmdline)})"
    text = " ".join(cmdline)
    if ZYGOTE.search(text) and name and not name.startswith("python"):  # forked from the tests' zygote
        return f"hri-lab {name}"
    for kind, pattern in PROGRAM_KINDS[:3]:  # before the CLI: they may be started through it
        if pattern.search(text):
            return kind
    if found := CLI.search(text):
        return f"hri-lab {found.group(1)}"
    for kind, pattern in PROGRAM_KINDS[3:]:
        if pattern.search(text):
            return kind
    return os.path.basename(cmdline[0]) if cmdline else "?"


class ProcessTree:
    """The CPU seconds of this process's descendants, sampled on a thread until `stop()`."""

    def __init__(self, period_s: float = SAMPLE_PERIOD_S) -> None:
        self.period_s = period_s
        self.seen: dict[tuple[int, float], list] = {}  # (pid, start time) -> [kind, CPU s]
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="suite-time-programs", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        me = psutil.Process()
        while not self._stop.is_set():
            self.sample(me)
            self._stop.wait(self.period_s)

    def sample(self, root: psutil.Process) -> None:
        for child in root.children(recursive=True):
            try:
                with child.oneshot():
                    key = (child.pid, child.create_time())
                    times = child.cpu_times()
                    if key not in self.seen:
                        self.seen[key] = [program_kind(child.cmdline(), child.name()), 0.0]
                    self.seen[key][1] = times.user + times.system
            except psutil.Error:  # gone between the listing and the reading
                continue

    def stop(self) -> list[tuple[str, int, float]]:
        """(kind, processes, CPU s), the most CPU first."""
        self._stop.set()
        self._thread.join()
        cpu: Counter[str] = Counter()
        count: Counter[str] = Counter()
        for kind, seconds in self.seen.values():
            cpu[kind] += seconds
            count[kind] += 1
        return [(kind, count[kind], seconds) for kind, seconds in cpu.most_common()]


def busy_share(before: tuple[int, int], after: tuple[int, int]) -> float:
    """The share (0..1) of the machine's CPU time that was busy between two readings of stat_ticks."""
    busy, every = after[0] - before[0], after[1] - before[1]
    return busy / every if every > 0 else 0.0


class CoreUse:
    """How busy the machine's cores were, read from /proc/stat every `period_s` on a thread until `stop()`."""

    def __init__(self, period_s: float = CORE_PERIOD_S) -> None:
        self.period_s = period_s
        self.started = time.monotonic()
        self.readings: list[tuple[float, float]] = []  # (s since the start, busy share over the period before)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="suite-time-cores", daemon=True)
        self._thread.start()

    @staticmethod
    def _read() -> tuple[int, int]:
        with open("/proc/stat") as stat:
            return stat_ticks(stat.readline())  # the first line: all the cores

    def _run(self) -> None:
        last = self._read()
        while not self._stop.wait(self.period_s):
            now = self._read()
            self.readings.append((time.monotonic() - self.started, busy_share(last, now)))
            last = now

    def stop(self, window_s: float = CORE_WINDOW_S) -> tuple[list[float], float]:
        """(the mean busy share of each `window_s` of the run, of the whole run)."""
        self._stop.set()
        self._thread.join()
        windows: dict[int, list[float]] = {}
        for at, share in self.readings:
            windows.setdefault(int(at // window_s), []).append(share)
        means = [sum(v) / len(v) for _, v in sorted(windows.items())]
        whole = sum(share for _, share in self.readings) / len(self.readings) if self.readings else 0.0
        return means, whole


def own_cpu_s() -> float:
    """CPU seconds (user + system) of this process alone."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    return own.ru_utime + own.ru_stime


def cpu_s() -> float:
    """CPU seconds (user + system) of this process and of its children that have ended."""
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own_cpu_s() + children.ru_utime + children.ru_stime


class SuiteTime:
    """One run's figures (an object per run: a run inside a run keeps its own)."""

    def __init__(self, programs: ProcessTree | None = None, cores: CoreUse | None = None) -> None:
        self.started = time.monotonic()
        self.programs = programs
        self.cores = cores
        self.worker_ends: dict[str, float] = {}  # worker -> when its last test's report ended (epoch s)
        self.cpu_at_start: dict[str, tuple[float, float]] = {}  # test -> (CPU s with children, own CPU s)
        self.files: dict[str, dict[str, float]] = {}  # file -> tests, wall_s, setup_s, cpu_s, own_cpu_s

    @pytest.hookimpl(hookwrapper=True)
    def pytest_runtest_setup(self, item):
        self.cpu_at_start[item.nodeid] = (cpu_s(), own_cpu_s())
        yield

    @pytest.hookimpl(hookwrapper=True)
    def pytest_runtest_makereport(self, item, call):
        outcome = yield
        if call.when == "teardown":  # the test's CPU, from before its setup to after its teardown
            with_children, own = self.cpu_at_start.pop(item.nodeid, (cpu_s(), own_cpu_s()))
            outcome.get_result().user_properties += [(KEY, cpu_s() - with_children), (OWN_KEY, own_cpu_s() - own)]

    def pytest_runtest_logreport(self, report) -> None:  # on xdist's controller: every worker's reports
        entry = self.files.setdefault(
            report.nodeid.split("::")[0], {"tests": 0, "wall_s": 0.0, "setup_s": 0.0, "cpu_s": 0.0, "own_cpu_s": 0.0}
        )
        entry["wall_s"] += report.duration
        worker = getattr(getattr(getattr(report, "node", None), "gateway", None), "id", "the run")  # xdist's, or none
        self.worker_ends[worker] = max(self.worker_ends.get(worker, 0.0), getattr(report, "stop", 0.0))
        if report.when == "setup":
            entry["tests"] += 1
            entry["setup_s"] += report.duration
        elif report.when == "teardown":
            entry["cpu_s"] += dict(report.user_properties).get(KEY, 0.0)
            entry["own_cpu_s"] += dict(report.user_properties).get(OWN_KEY, 0.0)

    def pytest_terminal_summary(self, terminalreporter) -> None:
        if not self.files:
            return
        rows = sorted(self.files.items(), key=lambda kv: -kv[1]["wall_s"])
        write = terminalreporter.write_line
        wall, cpu = sum(e["wall_s"] for _, e in rows), sum(e["cpu_s"] for _, e in rows)
        write("")
        write(f"suite time by file: {len(rows)} files, {wall:.0f} s of test wall time, {cpu:.0f} s of CPU")
        write(f"{'wall s':>7} {'setup s':>7} {'CPU s':>7} {'own s':>7} {'tests':>5}  file")
        for path, e in rows:
            write(
                f"{e['wall_s']:7.1f} {e['setup_s']:7.1f} {e['cpu_s']:7.1f} {e['own_cpu_s']:7.1f} {int(e['tests']):5d}  {path}"
            )
        if self.programs is not None:
            kinds = self.programs.stop()
            write("")
            write(f"CPU by program: {sum(n for _, n, _ in kinds)} processes, {sum(c for *_, c in kinds):.1f} s of CPU")
            write(f"{'CPU s':>7} {'procs':>5}  program")
            for kind, n, seconds in kinds:
                write(f"{seconds:7.1f} {n:5d}  {kind}")
        if self.cores is not None:
            windows, whole = self.cores.stop()
            write("")
            write(
                f"the cores busy, each {CORE_WINDOW_S:g} s: "
                + " ".join(f"{100 * share:.0f}" for share in windows)
                + f" %; {100 * whole:.0f} % over the run"
            )
            began = time.time() - (time.monotonic() - self.started)  # the run's start, epoch s
            write(
                "each worker's last test ended: "
                + ", ".join(f"{worker} at {end - began:.0f} s" for worker, end in sorted(self.worker_ends.items()))
            )
        load = " ".join(f"{x:.2f}" for x in os.getloadavg())
        write(f"the run: {time.monotonic() - self.started:.0f} s; load average at its end {load}")
        if out := os.environ.get("HRI_LAB_SUITE_TIME"):
            Path(out).write_text(json.dumps(dict(rows), indent=1))


def pytest_configure(config) -> None:
    controller = not hasattr(config, "workerinput")  # xdist's workers have it; the table is the controller's
    programs = ProcessTree() if controller and os.environ.get("HRI_LAB_SUITE_PROGRAMS") else None
    cores = CoreUse() if controller and os.environ.get("HRI_LAB_SUITE_CORES") else None
    config.pluginmanager.register(SuiteTime(programs, cores), "suite_time_figures")
