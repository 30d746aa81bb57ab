"""The lab's experiment (Table 1 of the handout), headless and faster than real time.

A trial (docs/design.md, "The experiment"): the robot at the start pose; the person holds the box grasped a
few cm in front of the plate; lifting starts with f_n_min (default 10 N) and the robot approaches
until it presses the box; once the grip is in the band the person lets go of the grasp and only
pushes with the palm; then carries the box along the pick-and-place path.

Success is judged by the world's own state, never by what a controller returns: at the end of the
person's path the box is within `goal_tolerance` of its start + the path's displacement, and held
by both plate and palm; along the way it never slipped 2 cm in the palm, neither the plate nor the
palm lost contact for more than 0.2 s, no robot reflex, within 60 s, and no faster than the
person's path takes. Nine trials = three participants x three tries.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from concurrent.futures import FIRST_COMPLETED, wait
from dataclasses import asdict, dataclass, field, replace
from typing import Any

import numpy as np

from sim.controllers.interface import Controller, LiftingParams
from sim.controllers.plugin import controller_factory as default_factory
from sim.controllers.sp import SPController
from sim.person.participants import PARTICIPANTS, TABLE_1, Participant
from sim.procedures.monitor import TrialRules
from sim.procedures.workers import worker_pool
from sim.recording.trial import TrialObserver
from sim.world import World, WorldConfig


@dataclass(frozen=True)
class Setup:
    """What an experiment changes from the defaults (the app turns parameter overrides into it):
    the controller's LiftingParams, the world's WorldConfig, and fields of every participant
    (set before a try varies speed and squeeze)."""

    params: LiftingParams = field(default_factory=LiftingParams)
    config: WorldConfig = field(default_factory=WorldConfig)
    person: tuple[tuple[str, Any], ...] = ()  # (Participant field, value)

    def with_lifting(self, name: str, value: Any) -> Setup:
        return replace(self, params=replace(self.params, **{name: value}))

    def with_config(self, part: str, name: str, value: Any) -> Setup:
        """A field of a part of WorldConfig (sensor, box, plate_contact, ...)."""
        return replace(
            self, config=replace(self.config, **{part: replace(getattr(self.config, part), **{name: value})})
        )

    def with_person(self, name: str, value: Any) -> Setup:
        return replace(self, person=tuple((k, v) for k, v in self.person if k != name) + ((name, value),))

    def participant(self, person: Participant) -> Participant:
        return replace(person, **dict(self.person))


@dataclass
class TrialResult:
    index: int
    participant: str
    attempt: int
    seed: int
    success: bool
    duration: float  # s from start of lifting to the end of the hold (or to the failure)
    f_n_min: float  # N, plate normal force once the person let go (min, max)
    f_n_max: float
    max_friction_ratio: float  # max |f_t| / (mu f_n) at the plate, mu = the controller's mu
    slip: float  # m, max slip of the box in the palm
    reason: str  # why it failed ("" on success)
    steps: int = 0
    files: dict = field(default_factory=dict)  # what the trial left: recording, png, svg (paths)

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass
class Trial:
    """One trial, steppable (tests can intervene between steps)."""

    participant: Participant
    seed: int
    controller: Controller = field(default_factory=SPController)
    config: WorldConfig = field(default_factory=WorldConfig)
    rules: TrialRules = field(default_factory=TrialRules)
    params: LiftingParams = field(default_factory=LiftingParams)
    index: int = 0
    attempt: int = 1
    observer: Callable[[Trial], None] | None = None  # called after every step (recording, figures)

    def __post_init__(self) -> None:
        rng = np.random.default_rng(self.seed)
        self.person = self.participant.varied(rng)
        self.world = World(self.config, self.controller, self.params)
        self.world.reset(self.person, seed=self.seed)
        self.world.start_lifting(self.rules.force)
        self.monitor = self.world.trial  # the success rule, applied by the world after every step
        self.monitor.rules = self.rules
        self.monitor.begin(self.world.time, self.participant.name, self.world)
        self.steps = 0

    @property
    def finished(self) -> bool:
        return self.monitor.finished

    @property
    def reason(self) -> str:
        return self.monitor.reason

    @property
    def slip(self) -> float:
        """m, the largest slip of the box in the palm so far."""
        return self.monitor.slip

    def step(self) -> bool:
        """Advance one control period; False once the trial is over."""
        if self.finished:
            return False
        self.world.step()
        self.steps += 1
        if self.observer is not None:
            self.observer(self)
        return not self.finished

    def run(self) -> TrialResult:
        while self.step():
            pass
        return self.result()

    def result(self) -> TrialResult:
        return TrialResult(
            index=self.index,
            participant=self.participant.name,
            attempt=self.attempt,
            seed=self.seed,
            success=self.finished and self.reason == "",
            duration=round(self.world.time, 3),
            f_n_min=float(self.monitor.f_n_low) if np.isfinite(self.monitor.f_n_low) else 0.0,
            f_n_max=float(self.monitor.f_n_high),
            max_friction_ratio=float(self.monitor.ratio),
            slip=float(self.monitor.slip),
            reason=self.reason if self.finished else "not finished",
            steps=self.steps,
        )


def trial_seed(seed: int, index: int) -> int:
    """A reproducible, well-mixed seed for trial `index` of an experiment seeded `seed`."""
    return int(np.random.SeedSequence([seed, index]).generate_state(1)[0])


def plan(trials: int = 9, participant: str | None = None, seed: int = 0) -> list[tuple[int, Participant, int, int]]:
    """(index, participant, attempt, seed) of each trial: participants x tries, as in the handout."""
    people = [PARTICIPANTS[participant]] if participant else [PARTICIPANTS[name] for name in TABLE_1]
    tries = -(-trials // len(people))
    order = [(p, a) for p in people for a in range(1, tries + 1)][:trials]
    return [(i, p, a, trial_seed(seed, i)) for i, (p, a) in enumerate(order)]


def run_trial(
    index: int,
    person: Participant,
    attempt: int,
    seed: int,
    rules: TrialRules = TrialRules(),
    controller_factory: Callable[[], Controller] = SPController,
    setup: Setup = Setup(),
    outputs=None,
) -> TrialResult:
    """outputs: a sim.recording.trial.TrialOutputs (recording and figure of the trial) or None."""
    trial = make_trial(index, person, attempt, seed, rules, controller_factory, setup)
    try:
        if outputs is None or not outputs.wanted:
            return trial.run()
        trial.observer = TrialObserver(trial, outputs)
        result = trial.run()
        result.files = trial.observer.finish(result)
        return result
    finally:
        getattr(trial.controller, "close", lambda: None)()  # a sandboxed plug-in's process ends with its trial


def make_trial(
    index: int,
    person: Participant,
    attempt: int,
    seed: int,
    rules: TrialRules = TrialRules(),
    controller_factory: Callable[[], Controller] = SPController,
    setup: Setup = Setup(),
) -> Trial:
    """A trial of `person` with the setup's parameters (its own copy of them)."""
    return Trial(
        setup.participant(person),
        seed,
        controller_factory(),
        config=setup.config,
        rules=rules,
        params=replace(setup.params),
        index=index,
        attempt=attempt,
    )


@dataclass(frozen=True)
class Job:
    """One trial of a batch: `key` says where its result belongs (controller, sweep point, ...)."""

    key: Any
    index: int
    participant: Participant
    attempt: int
    seed: int
    controller_factory: Callable[[], Controller] = SPController
    setup: Setup = Setup()
    rules: TrialRules = TrialRules()
    outputs: Any = None  # a TrialOutputs (sim/recording/trial.py): record and plot the trial

    def run(self) -> TrialResult:
        return run_trial(
            self.index,
            self.participant,
            self.attempt,
            self.seed,
            self.rules,
            self.controller_factory,
            self.setup,
            self.outputs,
        )


def run_jobs(
    work: list[Job],
    jobs: int = 1,
    on_result: Callable[[Job, TrialResult], None] | None = None,
    cancelled: Callable[[], bool] = lambda: False,
    mp_context=None,
) -> list[TrialResult | None]:
    """Run the trials, in order of `work`; in `jobs` worker processes (they die with this process)
    unless jobs == 1 and no mp_context is given (then here). Each trial has its own seed, so the
    results do not depend on `jobs`. Once `cancelled()`, no further trial starts (None in its
    place); the running ones finish."""
    results: list[TrialResult | None] = [None] * len(work)
    if jobs <= 1 and mp_context is None:
        for i, job in enumerate(work):
            if cancelled():
                break
            results[i] = job.run()
            if on_result:
                on_result(job, results[i])
        return results
    with worker_pool(jobs, mp_context) as pool:
        running: dict = {}
        queue = list(enumerate(work))
        while queue or running:
            while queue and len(running) < max(1, jobs) and not cancelled():
                i, job = queue.pop(0)
                running[pool.submit(Job.run, job)] = i
            if not running:
                break
            done, _ = wait(running, return_when=FIRST_COMPLETED)
            for future in done:
                i = running.pop(future)
                results[i] = future.result()
                if on_result:
                    on_result(work[i], results[i])
    return results


def run_experiment(
    trials: int = 9,
    participant: str | None = None,
    seed: int = 0,
    rules: TrialRules = TrialRules(),
    controller_factory: Callable[[], Controller] = SPController,
    on_result: Callable[[TrialResult], None] | None = None,
    jobs: int = 1,
    setup: Setup = Setup(),
    cancelled: Callable[[], bool] = lambda: False,
    mp_context=None,
    outputs=None,
) -> list[TrialResult]:
    """Run the trials (see run_jobs); returned in plan order (a cancel leaves out those not run).
    outputs: a TrialOutputs (sim/recording/trial.py) to record and plot every trial."""
    work = [
        Job(None, i, p, a, s, controller_factory, setup, rules, outputs)
        for i, p, a, s in plan(trials, participant, seed)
    ]
    results = run_jobs(work, jobs, (lambda job, r: on_result(r)) if on_result else None, cancelled, mp_context)
    return [r for r in results if r is not None]


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
) -> list[SweepRow]:
    """The same trials (participants, tries, seeds) at every point, all in one pool."""
    items = plan(trials, participant, seed)
    work = [
        Job(k, i, p, a, s, controller_factory, setup, rules)
        for k, (_, setup) in enumerate(points)
        for i, p, a, s in items
    ]
    results = run_jobs(work, jobs, (lambda job, r: on_result(r)) if on_result else None)
    return [
        SweepRow(dict(values), [r for job, r in zip(work, results) if job.key == k])
        for k, (values, _) in enumerate(points)
    ]


def aggregate(results: list[TrialResult]) -> dict:
    """One participant's trials in one number each: successes, mean time of the successes (s),
    mean f_n min and max (N), mean max friction ratio, mean and max slip (m)."""
    ok = [r for r in results if r.success]
    return {
        "successes": len(ok),
        "trials": len(results),
        "mean_duration_success": float(np.mean([r.duration for r in ok])) if ok else None,
        "f_n_min": float(np.mean([r.f_n_min for r in results])),
        "f_n_max": float(np.mean([r.f_n_max for r in results])),
        "friction_ratio": float(np.mean([r.max_friction_ratio for r in results])),
        "slip_mean": float(np.mean([r.slip for r in results])),
        "slip_max": float(np.max([r.slip for r in results])),
    }


def by_participant(results: Iterable[TrialResult]) -> dict[str, list[TrialResult]]:
    out: dict[str, list[TrialResult]] = {}
    for r in results:
        out.setdefault(r.participant, []).append(r)
    return out


def sweep_json(rows: list[SweepRow]) -> dict:
    """The sweep as data (one point per row; per participant the aggregate; every trial)."""
    return {
        "parameters": list(rows[0].values) if rows else [],
        "points": [
            {
                "values": row.values,
                "participants": {p: aggregate(rs) for p, rs in by_participant(row.results).items()},
                "trials": [r.as_dict() for r in row.results],
            }
            for row in rows
        ],
    }


def format_sweep(rows: list[SweepRow], title: str = "") -> str:
    """One line per (point, participant): successes, time, slip, f_n range, friction ratio."""
    names = list(rows[0].values) if rows else []
    head = "".join(f"{n:>10} " for n in names)
    header = f"{head}{'participant':<11} {'ok':>4} {'time s':>7} {'slip mm mean/max':>17} {'f_n min..max':>13} {'|ft|/mu fn':>10}"
    lines = ([title] if title else []) + [header, "-" * len(header)]
    for row in rows:
        values = "".join(f"{v:>10g} " if isinstance(v, (int, float)) else f"{v!s:>10} " for v in row.values.values())
        for person, rs in by_participant(row.results).items():
            a = aggregate(rs)
            time_s = f"{a['mean_duration_success']:.1f}" if a["successes"] else "-"
            slip = f"{a['slip_mean'] * 1000:.1f}/{a['slip_max'] * 1000:.1f}"
            lines.append(
                f"{values}{person:<11} {a['successes']}/{a['trials']:<2} {time_s:>7} {slip:>17} "
                f"{a['f_n_min']:>6.1f}..{a['f_n_max']:<5.1f} {a['friction_ratio']:>10.2f}"
            )
    lines.append("-" * len(header))
    return "\n".join(line.rstrip() for line in lines)


def summary(results: list[TrialResult]) -> dict:
    ok = [r for r in results if r.success]
    return {
        "trials": len(results),
        "successes": len(ok),
        "success_rate": len(ok) / len(results) if results else 0.0,
        "mean_duration_success": float(np.mean([r.duration for r in ok])) if ok else None,
    }


def format_table(results: list[TrialResult], title: str = "") -> str:
    """The Table 1 of the handout as text; `title` (e.g. the parameters that differ from the
    defaults) goes above it."""
    header = f"{'#':>2}  {'participant':<11} {'try':>3}  {'success':<7} {'time s':>7} {'min f_n':>8} {'max f_n':>8} {'max |ft|/mu fn':>15} {'slip mm':>8}  reason"
    lines = ([title] if title else []) + [header, "-" * len(header)]
    for r in results:
        lines.append(
            f"{r.index + 1:>2}  {r.participant:<11} {r.attempt:>3}  {'yes' if r.success else 'NO':<7} {r.duration:>7.2f} "
            f"{r.f_n_min:>8.2f} {r.f_n_max:>8.2f} {r.max_friction_ratio:>15.2f} {r.slip * 1000:>8.1f}  {r.reason}"
        )
    s = summary(results)
    lines.append("-" * len(header))
    lines.append(f"success: {s['successes']}/{s['trials']}")
    return "\n".join(lines)


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
    cancelled: Callable[[], bool] = lambda: False,
    jobs: int = 1,
    mp_context=None,
    setup: Setup = Setup(),
    outputs=None,
) -> Comparison:
    """Run the comparison (see run_jobs: `jobs` processes, stops handing out trials once
    `cancelled()`). controller_factory(name) -> factory of new controllers (default: the
    built-in ones). outputs: a TrialOutputs to record and plot every trial (files prefixed with
    the controller)."""
    make = controller_factory or default_factory
    items = comparison_plan(controllers, trials, participants, seed)
    work = [
        Job(
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
    done = run_jobs(work, jobs, (lambda job, r: on_result(job.key, r)) if on_result else None, cancelled, mp_context)
    results: Comparison = {name: {} for name in controllers}
    for item, result in zip(items, done):
        if result is not None:
            results[item.controller].setdefault(item.participant.name, []).append(result)
    return results


def format_comparison(results: Comparison, title: str = "") -> str:
    """Per participant, per controller: successes, mean time, f_n range, friction margin, slip."""
    names = list(results)
    header = f"{'participant':<11} " + " | ".join(f"{n:^44}" for n in names)
    sub = f"{'':<11} " + " | ".join(
        f"{'ok':>4} {'time s':>7} {'f_n min..max':>13} {'|ft|/mu fn':>10} {'slip mm':>7}" for _ in names
    )
    lines = ([title] if title else []) + [header, sub, "-" * len(sub)]
    people = list(dict.fromkeys(person for by in results.values() for person in by))
    for person in people:
        cells = []
        for name in names:
            rs = results[name].get(person, [])
            if not rs:  # not run (a cancelled comparison)
                cells.append(f"{'-':^44}")
                continue
            ok = [r for r in rs if r.success]
            time_s = f"{np.mean([r.duration for r in ok]):.1f}" if ok else "-"
            f_lo, f_hi = np.mean([r.f_n_min for r in rs]), np.mean([r.f_n_max for r in rs])
            cells.append(
                f"{len(ok)}/{len(rs):<2} {time_s:>7} {f_lo:>6.1f}..{f_hi:<5.1f} {np.mean([r.max_friction_ratio for r in rs]):>10.2f} "
                f"{np.mean([r.slip for r in rs]) * 1000:>7.1f}"
            )
        lines.append(f"{person:<11} " + " | ".join(cells))
    totals = []
    for name in names:
        rs = [r for by in results[name].values() for r in by]
        totals.append(f"{sum(r.success for r in rs)}/{len(rs)} succeeded")
    lines.append("-" * len(sub))
    lines.append(f"{'all':<11} " + " | ".join(f"{t:^44}" for t in totals))
    return "\n".join(line.rstrip() for line in lines)
