"""The Gradescope bundle run the way Gradescope runs it ([its autograder specification](
https://gradescope-autograders.readthedocs.io/en/latest/specs/), docs/course-scale.md): a root laid
out like /autograder — the bundle unzipped into source/, setup.sh and run_autograder beside it —
then `setup.sh` once, as root, which finds (or installs) a Python >= 3.11, checks it and installs
the lab from the bundle's own source into a fresh virtual environment (roslibpy too: the bundle
grades services), then `run_autograder` once per submission with the files in submission/, which
writes results/results.json. Nothing of this checkout's venv is used after setup.sh: the
submissions are graded by the bundle's own install. The only change from Gradescope's layout: the
root is a temporary folder ($HRI_LAB_GRADESCOPE_ROOT) instead of /autograder.

What setup.sh reuses here, as a machine that built the image before would: uv's and pip's caches
of the downloaded packages, and numba's compiled kernels of this checkout when the bundle's sim/ is
byte for byte this checkout's (`sim.kernel_cache.sources_hash`): they are put where numba keeps
them beside the bundle's sources, with their stamp, before setup.sh runs, and numba itself decides
whether they fit (each kernel's source hash, numba's version, the CPU); its warm-up compiles what
does not. Compiling them from scratch is what `make .venv/.kernels` does with the same warm-up
(sim/warm_up.py). Everything else setup.sh does, it does from scratch: the venv, the install.

Graded here: a controller file (the lab's own SP, which the course's bundle flags: the one passing
grade through a bundle, tests/e2e/test_autograder.py runs the rest with this checkout's Python), a
roslibpy services node and a rospy services node (each with the other part missing or broken, so
every report's shape is seen)."""

import json
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from sim.kernel_cache import sources_hash

TESTS = Path(__file__).resolve().parents[1]
SIM = TESTS.parent / "sim"
SETUP_TIMEOUT = 2400.0  # s: a fresh venv from the package cache and the kernels compiled, on a loaded machine
RUN_TIMEOUT = 1200.0  # s: a whole battery, and a lab started for the services


IMAGE_PATH = (
    "/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin"  # an Ubuntu image's: its python3 is Ubuntu's
)


def clean_env(**extra: str) -> dict:
    """The environment of Gradescope's harness: none of this checkout's venv or settings, and its
    image's PATH (not this machine's: no pyenv, no venv before the system's python3)."""
    keep = {k: v for k, v in os.environ.items() if not k.startswith(("HRI_LAB_", "VIRTUAL_ENV", "PYTHON"))}
    return keep | {"PATH": IMAGE_PATH} | extra


@pytest.fixture(scope="module")
def autograder(tmp_path_factory) -> Path:
    """/autograder after the image was built: the bundle unzipped, setup.sh run."""
    root = tmp_path_factory.mktemp("gradescope") / "autograder"
    bundle = root.parent / "autograder.zip"
    made = subprocess.run(
        [sys.executable, "-m", "app.cli", "autograder", "-o", str(bundle), "--seed", "31", "--services"]
        + ["--hide-until-due", "--reference", "flag"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert made.returncode == 0, made.stderr
    with zipfile.ZipFile(bundle) as z:
        z.extractall(root / "source")
    for name in ("setup.sh", "run_autograder"):  # Gradescope copies them to /autograder, executable
        shutil.copy(root / "source" / name, root / name)
        (root / name).chmod(0o755)
    bundled_sim = root / "source" / "hri-lab" / "sim"
    reuse_kernels(SIM, bundled_sim)
    setup = subprocess.run(
        [str(root / "setup.sh")],
        capture_output=True,
        text=True,
        timeout=SETUP_TIMEOUT,
        cwd=root,
        env=clean_env(HRI_LAB_GRADESCOPE_ROOT=str(root)),
    )
    assert setup.returncode == 0, setup.stdout[-3000:] + setup.stderr[-3000:]
    assert "setup.sh: Python 3." in setup.stdout
    assert (root / "hri-lab" / "bin" / "python").exists()
    return root


def reuse_kernels(checkout: Path, bundled: Path) -> int:
    """This checkout's compiled kernels (numba's index and data files) and their stamp
    (sim/kernel_cache.py) copied beside the bundle's sources when the two sim/ are byte-identical;
    how many files were copied (0 if not)."""
    if sources_hash(checkout) != sources_hash(bundled):
        return 0
    files = [*checkout.rglob("__pycache__/*.nb[ic]"), checkout / "__pycache__" / "kernels.sha256"]
    for path in files:
        (bundled / path.relative_to(checkout)).parent.mkdir(exist_ok=True)
        shutil.copy(path, bundled / path.relative_to(checkout))
    return len(files)


def submit(root: Path, files: dict[str, str]) -> dict:
    """One submission: submission/ holds `files`, run_autograder grades it; its results.json."""
    for folder in ("submission", "results"):
        shutil.rmtree(root / folder, ignore_errors=True)
    (root / "submission").mkdir()
    for name, text in files.items():
        (root / "submission" / name).write_text(text)
    done = subprocess.run(
        [str(root / "run_autograder")],
        capture_output=True,
        text=True,
        timeout=RUN_TIMEOUT,
        cwd=root,
        env=clean_env(HRI_LAB_GRADESCOPE_ROOT=str(root)),
    )
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    results = json.loads((root / "results" / "results.json").read_text())
    assert results["score"] == sum(t["score"] for t in results["tests"])
    return results


def by_section(results: dict) -> dict[str, list[dict]]:
    sections: dict[str, list[dict]] = {}
    for test in results["tests"]:
        sections.setdefault(test["name"].split(":")[0], []).append(test)
    return sections


def test_a_controller_file(autograder):
    """The lab's own SP, flagged (--reference flag): graded as any file, the flag first and not
    counted; every test hidden until the due date (--hide-until-due), the score shown."""
    results = submit(autograder, {"cooperative_lifting.py": (TESTS / "controllers" / "reference_sp.py").read_text()})
    for test in results["tests"]:  # Gradescope's results.json
        assert set(test) == {"name", "score", "max_score", "output", "visibility"}
        assert 0 <= test["score"] <= test["max_score"]
    flag = results["tests"][0]
    assert flag["max_score"] == 0
    assert "FLAGGED" in flag["output"]
    assert "imports sim.controllers.sp" in flag["output"]
    sections = by_section(results)
    controller = sections["probe"] + sections["experiment"] + sections["robustness"]
    assert len(controller) == 13 + 9 + 2
    assert sum(t["score"] for t in controller) == sum(t["max_score"] for t in controller) == 130.0
    # no services_node.py: 0 of the services' 15 points, one test saying why
    assert [(t["score"], t["max_score"]) for t in sections["services"]] == [(0.0, 15.0)]
    assert results["score"] == 130.0
    assert "PASS" in results["output"]
    assert "seed 31, a private seed" in results["output"]
    assert "bubblewrap cannot run" not in results["output"]
    assert {t["visibility"] for t in results["tests"]} == {"after_due_date"}
    assert results["visibility"] == "visible"


def test_a_roslibpy_node(autograder):
    node = (TESTS / "nodes" / "services_solution.py").read_text()  # the roslibpy template, filled in
    results = submit(autograder, {"services_node.py": node, "cooperative_lifting.py": "class CooperativeLifting(:\n"})
    sections = by_section(results)
    assert len(sections["services"]) == 10
    assert all(t["score"] == t["max_score"] > 0 for t in sections["services"]), sections["services"]
    assert [(t["score"], t["max_score"]) for t in sections["controller"]] == [(0.0, 130.0)]  # cannot be loaded
    assert results["score"] == 15.0
    assert "SyntaxError" in results["output"]


def test_a_rospy_node(autograder):
    """The rospy template as printed (unfilled): run through the bundle's `hri-lab run`, with the
    lab's rospy layer and message packages from the bundle's install; 1/15, the done example."""
    node = subprocess.run(
        [sys.executable, "-m", "app.cli", "template", "services"], capture_output=True, text=True, check=True
    ).stdout
    # the controller part fails at its import (graded whole by test_a_controller_file: one battery per file)
    results = submit(autograder, {"services_node.py": node, "cooperative_lifting.py": "import not_a_module_here\n"})
    services = by_section(results)["services"]
    assert len(services) == 10
    assert [t["name"] for t in services if t["score"] > 0] == [
        "services: /add_two_ints: sum of two int64 (exact near 2^63)"
    ]
    assert [(t["score"], t["max_score"]) for t in by_section(results)["controller"]] == [(0.0, 130.0)]
    assert results["score"] == 1.0
    assert "not_a_module_here" in results["output"]


def test_setup_stops_where_there_is_no_python_it_can_use(tmp_path):
    """An image whose python3 is 3.10 and whose apt has no python3.11: setup.sh stops, naming the
    base image to pick (stubs stand in for the image's python3 and apt-get; nothing is installed)."""
    stubs = tmp_path / "bin"
    stubs.mkdir()
    (stubs / "python3").write_text('#!/bin/bash\n[ "$1" = --version ] && echo "Python 3.10.12" && exit 0\nexit 1\n')
    (stubs / "apt-get").write_text(  # the lists update; the package is not found (no dirname: bash alone)
        '#!/bin/bash\necho "apt-get $*" >> "${0%/*}/apt.log"\n[ "$1" = update ] && exit 0\nexit 100\n'
    )
    for stub in stubs.iterdir():
        stub.chmod(0o755)
    bundle = tmp_path / "autograder.zip"
    subprocess.run(
        [sys.executable, "-m", "app.cli", "autograder", "-o", str(bundle), "--seed", "31", "--services"],
        check=True,
        capture_output=True,
        timeout=120,
    )
    with zipfile.ZipFile(bundle) as z:
        (tmp_path / "setup.sh").write_bytes(z.read("setup.sh"))
    done = subprocess.run(
        ["/bin/bash", str(tmp_path / "setup.sh")],
        capture_output=True,
        text=True,
        timeout=60,
        env={"PATH": str(stubs), "HRI_LAB_GRADESCOPE_ROOT": str(tmp_path / "root")},
    )
    assert done.returncode == 1
    assert "needs Python >= 3.11" in done.stderr
    assert "Python 3.10.12" in done.stderr
    assert "Ubuntu 24.04 base image" in done.stderr
    assert "install -y -qq python3.11 python3.11-venv" in (stubs / "apt.log").read_text()  # 22.04's package, tried
    assert not (tmp_path / "root").exists()
