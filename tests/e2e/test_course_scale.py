"""A whole course at once (docs/course-scale.md): a Dask cluster (a LocalCluster of two worker
processes here) grades a folder and runs trials exactly as the local run does; a task whose
worker dies is run again; a batch with --out resumes: up-to-date reports are skipped, a changed
file is graded again, --force grades all."""

import json
import os
import subprocess
from pathlib import Path

import pytest

from sim.procedures.runner import Job, run_jobs

from tests.lab_zygote import run_command
from tests.sim.procedures.test_runner import die_once  # a worker lost mid-task, as the local runner's test has it

CONTROLLERS = Path(__file__).resolve().parents[1] / "controllers"
RAISING = """class CooperativeLifting:
    def reset(self):
        pass

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        raise ZeroDivisionError("{why}")
"""


@pytest.fixture(scope="module")
def scheduler():
    """The address of a two-worker LocalCluster (one thread each, in processes of their own), closed after the module."""
    import dask
    from distributed import LocalCluster

    # a task may kill one worker and be run again; one that kills two is lost (KilledWorker)
    with (
        dask.config.set({"distributed.scheduler.allowed-failures": 1}),
        LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None, scheduler_port=0
        ) as cluster,
    ):
        yield cluster.scheduler_address


def cli(*args: str, check_status: int | None = None) -> subprocess.CompletedProcess:
    run = run_command(*args, timeout=600)
    if check_status is not None:
        assert run.returncode == check_status, run.stdout + run.stderr
    return run


def folder_of_three(root: Path) -> Path:
    """A file that passes the probes (the template filled in), one that raises in step, one that cannot load."""
    folder = root / "submissions"
    folder.mkdir()
    (folder / "good.py").write_text((CONTROLLERS / "template_filled.py").read_text())
    (folder / "raising.py").write_text(RAISING.format(why="a bug in step"))
    (folder / "syntax.py").write_text("class CooperativeLifting(:\n")
    return folder


def files_of(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def test_a_cluster_grades_a_folder_as_the_local_run_does(tmp_path, scheduler):
    folder = folder_of_three(tmp_path)
    quick = ("--only", "probe", "--quiet", "--seed", "7")
    local = cli("grade", str(folder), "--out", str(tmp_path / "local"), "--jobs", "2", *quick, check_status=1)
    remote = cli("grade", str(folder), "--out", str(tmp_path / "cluster"), "--scheduler", scheduler, *quick)
    assert remote.returncode == local.returncode and remote.stdout == local.stdout, remote.stderr
    reports = files_of(tmp_path / "local")
    assert set(reports) == {f"{n}.{e}" for n in ("good", "raising", "syntax") for e in ("txt", "json")} | {
        "summary.csv",
        "similarity.csv",
        "similarity.html",
    }
    assert files_of(tmp_path / "cluster") == reports  # byte for byte
    good = json.loads(reports["good.json"])
    assert good["points"] == good["max_points"] == 65.0
    assert good["seed"] == 7
    assert "ZeroDivisionError: a bug in step" in reports["raising.txt"].decode()
    assert "SyntaxError" in json.loads(reports["syntax.json"])["error"]


def test_the_environment_names_the_cluster_and_trials_run_there_as_here(scheduler):
    args = ("experiment", "--trials", "2", "--participant", "calm", "--seed", "3", "--quiet")
    local = cli(*args, "--jobs", "2", "--sweep", "alpha=0.4,0.5", check_status=0)
    env = {**os.environ, "HRI_LAB_SCHEDULER": scheduler}
    remote = run_command(*args, "--sweep", "alpha=0.4,0.5", timeout=600, env=env)
    assert remote.returncode == 0 and remote.stdout == local.stdout, remote.stderr
    assert "calm" in local.stdout
    assert "0.4" in local.stdout


def die(code: int) -> str:
    os._exit(code)


def test_a_task_whose_worker_dies_is_run_again_then_lost(tmp_path, scheduler):
    # one at a time: a task waiting on a worker that another task kills counts that death too
    assert run_jobs([Job("once", die_once, (str(tmp_path / "marker"),))], scheduler=scheduler) == ["second try"]
    (always,) = run_jobs([Job("always", die, (3,), lost=lambda why: f"lost: {why}")], scheduler=scheduler)
    assert always.startswith("lost: the worker processes running it died")


def test_a_batch_resumes_and_regrades_only_what_changed(tmp_path):
    folder = tmp_path / "submissions"
    folder.mkdir()
    for name in ("first", "second"):
        (folder / f"{name}.py").write_text(RAISING.format(why=f"{name} bug"))
    (folder / "syntax.py").write_text("class CooperativeLifting(:\n")
    out = tmp_path / "reports"
    grade = ("grade", str(folder), "--out", str(out), "--only", "probe", "--jobs", "2", "--quiet")
    cli(*grade, check_status=1)
    before = files_of(out)
    stamps = {p.name: p.stat().st_mtime_ns for p in out.iterdir()}
    report = json.loads(before["first.json"])
    assert report["seed"] == 0
    assert len(report["sha256"]) == 64

    again = cli(*grade, check_status=1)
    assert "skipped 3 up to date" in again.stderr
    assert files_of(out) == before
    assert all((out / n).stat().st_mtime_ns == t for n, t in stamps.items() if n != "summary.csv")

    (folder / "second.py").write_text(RAISING.format(why="second bug, fixed badly"))
    changed = cli(*grade, check_status=1)
    assert "skipped 2 up to date" in changed.stderr
    assert "fixed badly" in (out / "second.txt").read_text()
    assert json.loads((out / "second.json").read_text())["sha256"] != json.loads(before["second.json"])["sha256"]
    for untouched in ("first.json", "first.txt", "syntax.json"):
        assert (out / untouched).stat().st_mtime_ns == stamps[untouched]
    assert len((out / "summary.csv").read_text().splitlines()) == 4

    other_seed = cli(*grade, "--seed", "1", check_status=1)
    assert "skipped" not in other_seed.stderr
    forced = cli(*grade, "--seed", "1", "--force", check_status=1)
    assert "skipped" not in forced.stderr
    assert all((out / n).stat().st_mtime_ns != stamps[n] for n in ("first.json", "syntax.json"))


def test_a_scheduler_address_that_is_none_is_refused_with_its_reason():
    run = cli("grade", str(CONTROLLERS / "reference_sp.py"), "--scheduler", "not an address")
    assert run.returncode == 2
    assert "argument --scheduler: 'not an address' is not a Dask scheduler's address" in run.stderr
    assert "Traceback" not in run.stderr
