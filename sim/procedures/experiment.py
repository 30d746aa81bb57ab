"""The lab's experiment, headless: the Table 1 trials (participants x tries), comparisons of
controllers on the same trials, sweeps of parameters. One trial is sim/procedures/trial.py; the
trials of a batch run as jobs of sim/procedures/runner.py (here, in a local pool or on a Dask
cluster, the same results); their text tables are sim/procedures/tables.py.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from multiprocessing.context import BaseContext
from typing import Any

from sim.controllers.interface import Controller
from sim.controllers.plugin import controller_factory as default_factory
from sim.controllers.sp import SPController
from sim.monitor import TrialRules
from sim.person.participants import PARTICIPANTS, TABLE_1, Participant
from sim.procedures.runner import Job, never, run_jobs
from sim.procedures.trial import Setup, TrialResult, run_trial, trial_seed
from sim.recording.trial import TrialOutputs


def plan(trials: int = 9, participant: str | None = None, seed: int = 0) -> list[tuple[int, Participant, int, int]]:
    """(index, participant, attempt, seed) of each trial: participants x tries, as in the handout."""
    people = [PARTICIPANTS[participant]] if participant else [PARTICIPANTS[name] for name in TABLE_1]
    tries = -(-trials // len(people))
    order = [(p, a) for p in people for a in range(1, tries + 1)][:trials]
    return [(i, p, a, trial_seed(seed, i)) for i, (p, a) in enumerate(order)]


def trial_job(
    key: Any,
    index: int,
    participant: Participant,
    attempt: int,
    seed: int,
    controller_factory: Callable[[], Controller] = SPController,
    setup: Setup = Setup(),
    rules: TrialRules = TrialRules(),
    outputs: TrialOutputs | None = None,
) -> Job[TrialResult]:
    """One trial of a batch as a job (sim/procedures/runner.py); `key` says where its result belongs."""
    return Job(key, run_trial, (index, participant, attempt, seed, rules, controller_factory, setup, outputs))


def run_experiment(
    trials: int = 9,
    participant: str | None = None,
    seed: int = 0,
    rules: TrialRules = TrialRules(),
    controller_factory: Callable[[], Controller] = SPController,
    on_result: Callable[[TrialResult], None] | None = None,
    jobs: int = 1,
    setup: Setup = Setup(),
    cancelled: Callable[[], bool] = never,
    mp_context: BaseContext | None = None,
    outputs: TrialOutputs | None = None,
    scheduler: str | None = None,
) -> list[TrialResult]:
    """Run the trials (sim/procedures/runner.py's run_jobs: here, in `jobs` processes or on the Dask
    cluster at `scheduler`); returned in plan order (a cancel leaves out those not run).
    outputs: a TrialOutputs (sim/recording/trial.py) to record and plot every trial."""
    work = [
        trial_job(None, i, p, a, s, controller_factory, setup, rules, outputs)
        for i, p, a, s in plan(trials, participant, seed)
    ]
    results = run_jobs(work, jobs, _each(on_result), cancelled, mp_context, scheduler)
    return [r for r in results if r is not None]


def _each(on_result: Callable[[TrialResult], None] | None) -> Callable[[Job[TrialResult], TrialResult], None] | None:
    """run_jobs' on_result(job, result) from one that takes the result alone."""
    if on_result is None:
        return None
    return lambda job, result: on_result(result)


SweepPoint = tuple[dict[str, Any], Setup]  # ({parameter: value}, the setup with those values)


@dataclass
class SweepRow:
    values: dict[str, Any]
    results: list[TrialResult]


def run_sweep(
    points: list[SweepPoint],
    trials: int = 9,
    participant: str | None = None,
    seed: int = 0,
    controller_factory: Callable[[], Controller] = SPController,
    on_result: Callable[[TrialResult], None] | None = None,
    jobs: int = 1,
    rules: TrialRules = TrialRules(),
    scheduler: str | None = None,
) -> list[SweepRow]:
    """The same trials (participants, tries, seeds) at every point, all in one batch of jobs (one
    pool, or one task per trial and point on the Dask cluster at `scheduler`)."""
    items = plan(trials, participant, seed)
    work = [
        trial_job(k, i, p, a, s, controller_factory, setup, rules)
        for k, (_, setup) in enumerate(points)
        for i, p, a, s in items
    ]
    results = run_jobs(work, jobs, _each(on_result), scheduler=scheduler)
    return [
        SweepRow(dict(values), [r for job, r in zip(work, results) if job.key == k and r is not None])
        for k, (values, _) in enumerate(points)
    ]


COMPARISON_PARTICIPANTS = ("calm", "average", "hasty", "brisk", "tilting")
Comparison = dict[str, dict[str, list[TrialResult]]]  # controller -> participant -> trials


@dataclass(frozen=True)
class ComparedTrial:
    """One trial of a comparison: the same (participant, attempt, seed) runs once per controller."""

    controller: str
    index: int
    participant: Participant
    attempt: int
    seed: int


def comparison_plan(
    controllers: list[str], trials: int, participants: list[str] | None = None, seed: int = 0
) -> list[ComparedTrial]:
    """`trials` tries of each participant (default COMPARISON_PARTICIPANTS), the same seeds for
    every controller."""
    people = participants or list(COMPARISON_PARTICIPANTS)
    return [
        ComparedTrial(name, index, person, attempt, trial_seed)
        for name in controllers
        for who in people
        for index, person, attempt, trial_seed in plan(trials, who, seed)
    ]


def run_comparison(
    controllers: list[str],
    trials: int,
    participants: list[str] | None = None,
    seed: int = 0,
    controller_factory: Callable[[str], Callable[[], Controller]] | None = None,
    on_result: Callable[[ComparedTrial, TrialResult], None] | None = None,
    cancelled: Callable[[], bool] = never,
    jobs: int = 1,
    mp_context: BaseContext | None = None,
    setup: Setup = Setup(),
    outputs: TrialOutputs | None = None,
    scheduler: str | None = None,
) -> Comparison:
    """Run the comparison (see run_jobs: `jobs` processes or the Dask cluster at `scheduler`, stops
    handing out trials once `cancelled()`). controller_factory(name) -> factory of new controllers (default: the
    built-in ones). outputs: a TrialOutputs to record and plot every trial (files prefixed with
    the controller)."""
    make = controller_factory or default_factory
    items = comparison_plan(controllers, trials, participants, seed)
    work = [
        trial_job(
            item,
            item.index,
            item.participant,
            item.attempt,
            item.seed,
            make(item.controller),
            setup,
            outputs=replace(outputs, prefix=f"{item.controller}_", label=item.controller) if outputs else None,
        )
        for item in items
    ]
    each = (lambda job, r: on_result(job.key, r)) if on_result else None
    done = run_jobs(work, jobs, each, cancelled, mp_context, scheduler)
    results: Comparison = {name: {} for name in controllers}
    for item, result in zip(items, done):
        if result is not None:
            results[item.controller].setdefault(item.participant.name, []).append(result)
    return results
