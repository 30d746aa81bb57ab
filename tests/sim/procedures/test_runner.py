"""The one job runner (sim/procedures/runner.py): the same results here and in a pool, in work
order; a cancel stops handing out jobs; a job whose worker process dies is run again, then its
stand-in counts (a grader's job: its items at 0 points, saying so)."""

import os
from pathlib import Path

import pytest

from sim.procedures import runner
from sim.procedures.runner import Job, JobLost, run_jobs

from app.grading.battery import LOST, probes_job, robustness_job


def square(x: int) -> int:
    return x * x


def die(code: int) -> int:
    os._exit(code)


def die_once(marker: str) -> str:
    """Kills its worker process the first time (the marker file says it ran), then answers."""
    path = Path(marker)
    if not path.exists():
        path.write_text("died once")
        os._exit(3)
    return "second try"


def test_the_same_results_here_and_in_a_pool_in_work_order():
    work = [Job(k, square, (k,), first=k % 2 == 1) for k in range(7)]
    seen = []
    here = run_jobs(work, 1, lambda job, r: seen.append((job.key, r)))
    assert here == [k * k for k in range(7)]
    assert seen == [(k, k * k) for k in range(7)]
    seen.clear()
    assert run_jobs(work, 2, lambda job, r: seen.append((job.key, r))) == here
    assert sorted(seen) == [(k, k * k) for k in range(7)]


def test_a_cancel_stops_handing_out_jobs():
    done = []
    results = run_jobs(
        [Job(k, square, (k,)) for k in range(5)], 1, lambda job, r: done.append(r), lambda: len(done) >= 2
    )
    assert results == [0, 1, None, None, None]


def test_a_job_whose_worker_dies_is_run_again(tmp_path):
    work = [Job("a", square, (3,)), Job("b", die_once, (str(tmp_path / "marker"),)), Job("c", square, (4,))]
    assert run_jobs(work, 2) == [9, "second try", 16]


def test_a_job_that_kills_every_worker_stands_in_or_fails_the_batch(monkeypatch):
    work = [Job("dies", die, (3,), lost=lambda why: f"lost: {why}"), Job("fine", square, (5,))]
    lost, fine = run_jobs(work, 2)
    assert lost.startswith("lost: the worker process died")
    assert fine == 25
    with pytest.raises(JobLost, match="'dies'"):
        run_jobs([Job("dies", die, (3,))], 2)
    assert runner.RETRIES >= 1


def test_a_graders_lost_job_stands_in_as_its_items_at_zero():
    probes = probes_job(square, 0).stand_in("the worker process died (SIGKILL)")
    assert len(probes) == 13
    assert all(i.points == 0 and i.max_points == 5 for i in probes)
    assert probes[0].detail == LOST + "the worker process died (SIGKILL)"
    assert probes[0].mark == "FAILED"
    (item,) = robustness_job(0, square, 0).stand_in("gone")
    assert (item.section, item.points, item.max_points, item.detail) == ("robustness", 0.0, 10.0, "not graded: gone")
