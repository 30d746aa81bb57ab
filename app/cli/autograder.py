"""`hri-lab autograder -o autograder.zip`: the bundle Gradescope takes (docs/course-scale.md).

Gradescope's autograder (https://gradescope-autograders.readthedocs.io/en/latest/specs/) unzips
the bundle into /autograder/source, runs its `setup.sh` once as root to build the image, then,
for every submission, its `run_autograder` with the student's files in /autograder/submission/;
that writes /autograder/results/results.json. Ours:
- setup.sh installs bubblewrap (apt) and this very lab (its source is in the bundle, uv
  installs it with its pinned dependencies) into a virtual environment /autograder/hri-lab;
- run_autograder runs `python -m app.cli.autograder` (`grade_submission` below): the battery
  of `hri-lab grade` on the submission's controller file, with the bundle's seed, each item a test;
  with --services also the services exercises (`hri-lab grade-services`) of the submission's
  services_node.py, run against a lab started in the container with `serve --exercises`.
  Where bubblewrap cannot create its namespaces (Gradescope's container may forbid them) the file
  runs with the child-process limits alone, and the output says so: the container is the sandbox.
$HRI_LAB_GRADESCOPE_ROOT (default /autograder) moves the whole layout (the tests use it);
$HRI_LAB_PYTHON names the interpreter run_autograder uses.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import threading
import time
import zipfile
from pathlib import Path

from sim.controllers.plugin import DEFAULT_CLASS, PluginError, PluginFactory
from sim.controllers.sandbox import sandbox_unavailable
from sim.procedures.battery import battery, load_check, new_report, reference_items, run_items
from sim.procedures.report import PUBLIC_SEED, Report, seed_note

from app.cli.handout import lab_files

CONFIG = "hri-lab-autograder.json"  # in the bundle: the seed and how results are shown
SOURCE = "hri-lab"  # the lab's source in the bundle (uv installs it)
UV = "uv==0.13.8"  # the installer setup.sh runs (pip installs it first, into the lab's venv)
TEMPLATE_NAME = "cooperative_lifting.py"  # the name `hri-lab template` suggests for the file
SERVICES_NAME = "services_node.py"  # the name `hri-lab template services` suggests for the node (docs/students.md)
NODE_READY_TIMEOUT = 60.0  # s the student's node has to say "node ready" (both templates print it)
NODE_SETTLE_S = 5.0  # s more, after it, for the lab to have every exercise service the node advertised

PYTHON_NEEDED = (3, 11)  # pyproject.toml's requires-python
BASE_IMAGE = "Ubuntu 24.04"  # Gradescope's base image to pick: its python3 is 3.12 (22.04's, the default, is 3.10)

SETUP_SH = """#!/usr/bin/env bash
# Gradescope runs this once, as root, when it builds the image. Pick the {base_image} base image
# (python3 3.12); on Ubuntu 22.04 (python3 3.10) Ubuntu's python3.11 is installed. hri-lab {version}
# needs Python >= {needed}: this script finds or installs one, checks it, and stops with a message
# when there is none. Then bubblewrap (the sandbox) and this lab with its pinned dependencies{nodes}
# in a virtual environment of its own, and its compiled kernels.
set -euo pipefail
ROOT="${{HRI_LAB_GRADESCOPE_ROOT:-/autograder}}"
version_ok() {{ "$1" -c 'import sys; sys.exit(sys.version_info < ({needed_tuple}))' 2>/dev/null; }}
venv_ok() {{ "$1" -c 'import ensurepip, venv' 2>/dev/null; }}
apt_install() {{ apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" >/dev/null; }}
PYTHON=""
for candidate in python3 python3.13 python3.12 python3.11; do
  if command -v "$candidate" >/dev/null && version_ok "$candidate"; then PYTHON="$(command -v "$candidate")"; break; fi
done
if [ -z "$PYTHON" ]; then
  apt_install python3.11 python3.11-venv || true
  if command -v python3.11 >/dev/null && version_ok python3.11; then PYTHON="$(command -v python3.11)"; fi
fi
if [ -z "$PYTHON" ]; then
  echo "setup.sh: hri-lab needs Python >= {needed}; this image has $(python3 --version 2>&1) and no python3.11 package:" \
    "pick Gradescope's {base_image} base image" >&2
  exit 1
fi
venv_ok "$PYTHON" || apt_install "$(basename "$PYTHON")-venv"
command -v bwrap >/dev/null || apt_install bubblewrap
echo "setup.sh: $("$PYTHON" --version) at $PYTHON"
"$PYTHON" -m venv "$ROOT/hri-lab"
# uv installs the lab's pinned dependencies several times faster than pip; byte-compiled now, as pip
# does, since every submission's container starts from this image and would otherwise compile them
"$ROOT/hri-lab/bin/pip" install --quiet {uv}
"$ROOT/hri-lab/bin/uv" pip install --quiet --compile-bytecode --python "$ROOT/hri-lab/bin/python" \
  --editable "$ROOT/source/{source}{extras}"
# the simulation's compiled kernels, cached now rather than by every submission's grade
"$ROOT/hri-lab/bin/python" -c "from sim.warm_up import warm_up; warm_up()"
"""

RUN_AUTOGRADER = """#!/usr/bin/env bash
# Gradescope runs this for every submission: grades /autograder/submission/ and writes
# /autograder/results/results.json (python -m app.cli.autograder; docs/course-scale.md).
set -euo pipefail
ROOT="${{HRI_LAB_GRADESCOPE_ROOT:-/autograder}}"
PYTHON="${{HRI_LAB_PYTHON:-$ROOT/hri-lab/bin/python}}"
cd "$ROOT"
exec "$PYTHON" -m app.cli.autograder "$ROOT/source/{config}"
"""


def version() -> str:
    from importlib.metadata import version as installed

    return installed("hri-lab")


def build(args: argparse.Namespace) -> int:
    """Write the bundle; 2 when the lab's source is not where its packages are (a wheel install)."""
    if args.seed == PUBLIC_SEED and not args.public_seed:
        print(
            f"hri-lab autograder: seed {PUBLIC_SEED} is the public default: every student can run this grade at "
            "home and learn its numbers. Give the course's private --seed N (or $HRI_LAB_GRADE_SEED), or "
            "--public-seed for a trial run",
            file=sys.stderr,
        )
        return 2
    files = lab_files()
    if not files[0][0].is_file():
        print("hri-lab autograder: the lab's source (pyproject.toml) is not beside its packages", file=sys.stderr)
        return 2
    config = {
        "seed": args.seed,
        "hide_until_due": args.hide_until_due,
        "services": args.services,
        "reference": args.reference,
        "version": version(),
    }
    with zipfile.ZipFile(args.output, "w", zipfile.ZIP_DEFLATED) as bundle:
        for name, text in (
            (
                "setup.sh",
                SETUP_SH.format(
                    version=config["version"],
                    source=SOURCE,
                    base_image=BASE_IMAGE,
                    needed=".".join(map(str, PYTHON_NEEDED)),
                    needed_tuple=", ".join(map(str, PYTHON_NEEDED)),
                    nodes=" (and roslibpy, for students' roslibpy nodes)" if args.services else "",
                    extras="[nodes]" if args.services else "",
                    uv=UV,
                ),
            ),
            ("run_autograder", RUN_AUTOGRADER.format(config=CONFIG)),
        ):
            info = zipfile.ZipInfo(name)
            info.external_attr = 0o100755 << 16  # executable, as Gradescope runs them
            info.compress_type = zipfile.ZIP_DEFLATED
            bundle.writestr(info, text)
        bundle.writestr(CONFIG, json.dumps(config, indent=2) + "\n")
        for path, name in files:
            bundle.write(path, f"{SOURCE}/{name}")
    print(f"{args.output}: setup.sh, run_autograder, hri-lab {config['version']}, {seed_note(args.seed)}")
    return 0


def run(args: argparse.Namespace) -> int:
    return build(args)


# --- in Gradescope's container ---------------------------------------------------------------------
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
    from app.cli.grade_services import grade_services
    from app.cli.launch import running_server
    from app.cli.services_grading import EXERCISES

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
    """run_autograder's entry: `python -m app.cli.autograder CONFIG.json`."""
    argv = sys.argv[1:] if argv is None else argv
    config = json.loads(Path(argv[0]).read_text(encoding="utf-8"))
    root = Path(os.environ.get("HRI_LAB_GRADESCOPE_ROOT", "/autograder"))
    results = grade_submission(root, config)
    print(results["output"])
    return 0  # Gradescope reads the score from results.json; a failing submission is not an error


if __name__ == "__main__":
    raise SystemExit(main())
