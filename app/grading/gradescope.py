"""The Gradescope autograder in its container (the bundle `hri-lab autograder` writes, app/cli/autograder.py):
`run_autograder` runs `python -m app.grading.gradescope CONFIG.json`, which grades /autograder/submission/
as the bundle's config says (the battery of `hri-lab grade` on the controller file, with --services
also the services exercises of its services_node.py against a lab started here) and writes
/autograder/results/results.json, one test per item. $HRI_LAB_GRADESCOPE_ROOT (default /autograder)
moves the whole layout (the tests use it)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

from sim.controllers.plugin import DEFAULT_CLASS, PluginError, PluginFactory
from sim.controllers.sandbox import sandbox_unavailable

from app.grading.battery import battery, load_check, new_report, reference_items, run_items
from app.grading.report import Report

TEMPLATE_NAME = "cooperative_lifting.py"  # the name `hri-lab template` suggests for the file
SERVICES_NAME = "services_node.py"  # the name `hri-lab template services` suggests for the node (docs/students.md)
NODE_READY_TIMEOUT = 60.0  # s the student's node has to say "node ready" (both templates print it)
NODE_SETTLE_S = 5.0  # s more, after it, for the lab to have every exercise service the node advertised


def submission_file(folder: Path) -> Path | None:
    """The controller file of a submission: cooperative_lifting.py, else its only .py file."""
    files = sorted(folder.rglob("*.py"))
    named = [f for f in files if f.name == TEMPLATE_NAME]
    return named[0] if named else files[0] if len(files) == 1 else None


def results_json(reports: list[Report], notes: list[str], hide_until_due: bool) -> dict:
    """Gradescope's results.json of the reports: the score, one test per item; with hide_until_due
    the tests (their seed-drawn numbers) are shown only after the due date, the score at once."""
    parts = [report.gradescope() for report in reports]
    tests: list[dict] = [test for part in parts for test in part["tests"]]
    visibility = "after_due_date" if hide_until_due else "visible"
    for test in tests:
        test["visibility"] = visibility
    results: dict = {
        "score": float(sum(part["score"] for part in parts)),
        "output": "\n".join([*notes, *(part["output"] for part in parts)]),
        "tests": tests,
    }
    results["visibility"] = "visible"
    results["stdout_visibility"] = "hidden"
    return results


def grade_submission(root: Path, config: dict) -> dict:
    """Grade root/submission/ as the bundle's config says; the results.json written (and returned)."""
    notes: list[str] = []
    found = submission_file(root / "submission")
    seed = int(config.get("seed", 0))
    if found is None:
        report = new_report("submission", seed)
        report.error = f"no controller file: submit {TEMPLATE_NAME} (or a single .py file) with a class {DEFAULT_CLASS}"
    else:
        report = new_report(found.name, seed)
        unavailable = sandbox_unavailable()
        if unavailable:
            notes.append(
                f"bubblewrap cannot run in this container ({unavailable.splitlines()[0]}): the file ran in a "
                "process of its own with the child-process limits (memory, CPU time), the container as its sandbox"
            )
        factory = PluginFactory(str(found), sandboxed=not unavailable)
        try:
            factory = factory.carrying()
            loaded = load_check(factory, sandboxed=not unavailable)
            report.error = loaded.error or loaded.refused
            if loaded.reference and config.get("reference", "zero") == "zero":  # the lab's own: 0 points
                report.error = loaded.reference
        except PluginError as exc:
            report.error = str(exc)
        if not report.error:
            report.items = run_items(battery(factory, seed), os.cpu_count() or 1)
            if loaded.reference:  # the course flags it (--reference flag): graded, and said
                report.items = reference_items(loaded.reference) + report.items  # first, as hri-lab grade has it
    reports = [report]
    if config.get("services"):
        reports.append(services_report(root / "submission", seed))
    results = results_json(reports, notes, bool(config.get("hide_until_due")))
    out = root / "results"
    out.mkdir(parents=True, exist_ok=True)
    (out / "results.json").write_text(json.dumps(results, indent=2), encoding="utf-8")
    return results


def services_report(folder: Path, seed: int) -> Report:
    """The services exercises of folder's services_node.py: a lab started here with --exercises,
    the node connected to it (a rospy/rclpy program through `hri-lab run`, else run with --port,
    as the roslibpy template is), graded over HTTP once it says "node ready" (or after
    NODE_READY_TIMEOUT s: what it does not serve then is not provided)."""
    from app.grading.services import EXERCISES, grade_services
    from app.serving.launch import running_server

    found = sorted(folder.rglob(SERVICES_NAME))
    if not found:
        report = Report("services", "services", seed, full_points=sum(e.points for e in EXERCISES))
        report.error = f"no {SERVICES_NAME} in the submission (start from `hri-lab template services`)"
        return report
    node_file = found[0]
    text = node_file.read_text(encoding="utf-8", errors="replace")
    with running_server("--view", "none", "--exercises") as server:
        if "rospy" in text or "rclpy" in text:
            argv = [sys.executable, "-m", "app.cli", "run", "--url", server.url, str(node_file)]
        else:
            argv = [sys.executable, str(node_file), "--port", str(server.port)]
        node = subprocess.Popen(
            argv,
            cwd=node_file.parent,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            start_new_session=True,
        )
        ready = threading.Event()

        def watch() -> None:
            for line in node.stdout or ():
                if "node ready" in line:
                    ready.set()

        threading.Thread(target=watch, daemon=True).start()
        try:
            deadline = time.monotonic() + NODE_READY_TIMEOUT
            while not ready.is_set() and node.poll() is None and time.monotonic() < deadline:
                ready.wait(0.2)
            provided_by_nodes(server.url, [e.service for e in EXERCISES], NODE_SETTLE_S)
            report = grade_services(server.url, seed)
            report.subject = node_file.name
        finally:
            try:
                os.killpg(node.pid, signal.SIGKILL)
            except OSError:
                pass
            node.wait(timeout=10)
    return report


def provided_by_nodes(url: str, services: list[str], settle_s: float) -> list[str]:
    """Until a node provides each of `services` (`GET /services/NAME`'s node is not the lab), or
    `settle_s` s: a roslibpy node's "node ready" can come before the lab has the services it
    advertised (roslibpy does not wait), and a service graded then would count as not provided.
    Returns those still the lab's own."""
    import httpx

    from app.rosbridge.rosapi import LAB_NODE

    end = time.monotonic() + settle_s
    waiting = list(services)
    with httpx.Client(base_url=url, timeout=30) as client:
        while waiting and time.monotonic() < end:
            waiting = [s for s in waiting if client.get(f"/services/{s.strip('/')}").json().get("node") == LAB_NODE]
            if waiting:
                time.sleep(0.05)
    return waiting


def main(argv: list[str] | None = None) -> int:
    """run_autograder's entry: `python -m app.grading.gradescope CONFIG.json`."""
    argv = sys.argv[1:] if argv is None else argv
    config = json.loads(Path(argv[0]).read_text(encoding="utf-8"))
    root = Path(os.environ.get("HRI_LAB_GRADESCOPE_ROOT", "/autograder"))
    results = grade_submission(root, config)
    print(results["output"])
    return 0  # Gradescope reads the score from results.json; a failing submission is not an error


if __name__ == "__main__":
    raise SystemExit(main())
