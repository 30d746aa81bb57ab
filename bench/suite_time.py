"""Where the test suite's time goes: each test file's wall time (its tests' setup, call and teardown,
as pytest reports them) and its CPU time (the worker's own and its children's: the servers, nodes,
sandboxes and browsers it started), the longest first. CPU seconds are what a shared machine is
short of; wall seconds are what a worker waits.

    .venv/bin/python -m pytest -q -n 3 --dist loadfile --no-loadscope-reorder -p bench.suite_time [FILES]
    HRI_LAB_SUITE_TIME=times.json ...   # the table as JSON too

A pytest plugin (`-p bench.suite_time`), with or without xdist: each worker measures its tests and
hands the figures to the controller in the tests' reports; the table is printed at the end.
"""

from __future__ import annotations

import json
import os
import resource
import time
from pathlib import Path

import pytest

KEY = "suite_time_cpu_s"


def cpu_s() -> float:
    """CPU seconds (user + system) of this process and of its children that have ended."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


class SuiteTime:
    """One run's figures (an object per run: a run inside a run keeps its own)."""

    def __init__(self) -> None:
        self.started = time.monotonic()
        self.cpu_at_start: dict[str, float] = {}
        self.files: dict[str, dict[str, float]] = {}  # file -> tests, wall_s, setup_s, cpu_s

    @pytest.hookimpl(hookwrapper=True)
    def pytest_runtest_setup(self, item):
        self.cpu_at_start[item.nodeid] = cpu_s()
        yield

    @pytest.hookimpl(hookwrapper=True)
    def pytest_runtest_makereport(self, item, call):
        outcome = yield
        if call.when == "teardown":  # the test's CPU, from before its setup to after its teardown
            spent = cpu_s() - self.cpu_at_start.pop(item.nodeid, cpu_s())
            outcome.get_result().user_properties.append((KEY, spent))

    def pytest_runtest_logreport(self, report) -> None:  # on xdist's controller: every worker's reports
        entry = self.files.setdefault(
            report.nodeid.split("::")[0], {"tests": 0, "wall_s": 0.0, "setup_s": 0.0, "cpu_s": 0.0}
        )
        entry["wall_s"] += report.duration
        if report.when == "setup":
            entry["tests"] += 1
            entry["setup_s"] += report.duration
        elif report.when == "teardown":
            entry["cpu_s"] += dict(report.user_properties).get(KEY, 0.0)

    def pytest_terminal_summary(self, terminalreporter) -> None:
        if not self.files:
            return
        rows = sorted(self.files.items(), key=lambda kv: -kv[1]["wall_s"])
        write = terminalreporter.write_line
        wall, cpu = sum(e["wall_s"] for _, e in rows), sum(e["cpu_s"] for _, e in rows)
        write("")
        write(f"suite time by file: {len(rows)} files, {wall:.0f} s of test wall time, {cpu:.0f} s of CPU")
        write(f"{'wall s':>7} {'setup s':>7} {'CPU s':>7} {'tests':>5}  file")
        for path, e in rows:
            write(f"{e['wall_s']:7.1f} {e['setup_s']:7.1f} {e['cpu_s']:7.1f} {int(e['tests']):5d}  {path}")
        load = " ".join(f"{x:.2f}" for x in os.getloadavg())
        write(f"the run: {time.monotonic() - self.started:.0f} s; load average at its end {load}")
        if out := os.environ.get("HRI_LAB_SUITE_TIME"):
            Path(out).write_text(json.dumps(dict(rows), indent=1))


def pytest_configure(config) -> None:
    config.pluginmanager.register(SuiteTime(), "suite_time_figures")
