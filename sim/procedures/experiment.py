"""The lab's experiment (Table 1 of the handout), headless and faster than real time.

A trial (DESIGN.md section 8): the robot at the start pose; the person holds the box grasped a
few cm in front of the plate; lifting starts with f_n_min (default 10 N) and the robot approaches
until it presses the box; once the grip is in the band the person lets go of the grasp and only
pushes with the palm; then carries the box along the pick-and-place path.

Success = the box is never dropped (its slip relative to the palm stays below 2 cm and the robot
never loses contact for more than 0.2 s), no robot reflex, and the goal reached in under 60 s.
Nine trials = three participants x three tries.
"""
from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import asdict, dataclass, field
from typing import Callable

import numpy as np

from sim.controllers.interface import Controller, LiftingParams
from sim.person.human import PARTICIPANTS, TABLE_1, Participant
from sim.controllers.sp import SPController
from sim.procedures.monitor import TrialRules
from sim.world import World, WorldConfig


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

    def __post_init__(self) -> None:
        rng = np.random.default_rng(self.seed)
        self.person = self.participant.varied(rng)
        self.world = World(self.config, self.controller, self.params)
        self.world.reset(self.person, seed=self.seed)
        self.world.start_lifting(self.rules.force)
        self.monitor = self.world.trial  # the success rule, applied by the world after every step
        self.monitor.rules = self.rules
        self.monitor.begin(self.world.time, self.participant.name)
        self.steps = 0

    @property
    def finished(self) -> bool:
        return self.monitor.finished

    @property
    def reason(self) -> str:
        return self.monitor.reason

    def step(self) -> bool:
        """Advance one control period; False once the trial is over."""
        if self.finished:
            return False
        self.world.step()
        self.steps += 1
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
) -> TrialResult:
    return Trial(person, seed, controller_factory(), rules=rules, index=index, attempt=attempt).run()


def run_experiment(
    trials: int = 9,
    participant: str | None = None,
    seed: int = 0,
    rules: TrialRules = TrialRules(),
    controller_factory: Callable[[], Controller] = SPController,
    on_result: Callable[[TrialResult], None] | None = None,
    jobs: int = 1,
) -> list[TrialResult]:
    """Run the trials, in `jobs` processes when jobs > 1 (each trial has its own seed, so the
    results are the same whatever the number of processes); returned in plan order."""
    work = [(*item, rules, controller_factory) for item in plan(trials, participant, seed)]
    if jobs <= 1:
        results = []
        for args in work:
            results.append(run_trial(*args))
            if on_result:
                on_result(results[-1])
        return results
    with ProcessPoolExecutor(max_workers=jobs) as pool:
        futures = [pool.submit(run_trial, *args) for args in work]
        for future in as_completed(futures):
            if on_result:
                on_result(future.result())
        return [f.result() for f in futures]


def summary(results: list[TrialResult]) -> dict:
    ok = [r for r in results if r.success]
    return {
        "trials": len(results),
        "successes": len(ok),
        "success_rate": len(ok) / len(results) if results else 0.0,
        "mean_duration_success": float(np.mean([r.duration for r in ok])) if ok else None,
    }


def format_table(results: list[TrialResult]) -> str:
    """The Table 1 of the handout as text."""
    header = f"{'#':>2}  {'participant':<11} {'try':>3}  {'success':<7} {'time s':>7} {'min f_n':>8} {'max f_n':>8} {'max |ft|/mu fn':>15} {'slip mm':>8}  reason"
    lines = [header, "-" * len(header)]
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


def comparison_plan(controllers: list[str], trials: int, participants: list[str] | None = None,
                    seed: int = 0) -> list[ComparedTrial]:
    """`trials` tries of each participant (default COMPARISON_PARTICIPANTS), the same seeds for
    every controller."""
    people = participants or list(COMPARISON_PARTICIPANTS)
    return [ComparedTrial(name, index, person, attempt, trial_seed)
            for name in controllers for who in people
            for index, person, attempt, trial_seed in plan(trials, who, seed)]


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
) -> Comparison:
    """Run the comparison (in `jobs` processes; stops handing out trials once `cancelled()`).
    controller_factory(name) -> factory of new controllers (default: the built-in ones)."""
    from sim.controllers.plugin import controller_factory as default_factory

    make = controller_factory or default_factory
    work = comparison_plan(controllers, trials, participants, seed)
    results: Comparison = {name: {} for name in controllers}
    with ProcessPoolExecutor(max_workers=max(1, jobs), mp_context=mp_context) as pool:
        running = {}
        queue = list(work)
        while queue or running:
            while queue and len(running) < max(1, jobs) and not cancelled():
                item = queue.pop(0)
                running[pool.submit(run_trial, item.index, item.participant, item.attempt, item.seed,
                                    TrialRules(), make(item.controller))] = item
            if not running:
                break
            future = next(as_completed(running))
            item = running.pop(future)
            result = future.result()
            results[item.controller].setdefault(item.participant.name, []).append(result)
            if on_result:
                on_result(item, result)
    for by_person in results.values():
        for rs in by_person.values():
            rs.sort(key=lambda r: r.index)
    return results


def format_comparison(results: Comparison) -> str:
    """Per participant, per controller: successes, mean time, f_n range, friction margin, slip."""
    names = list(results)
    header = f"{'participant':<11} " + " | ".join(f"{n:^44}" for n in names)
    sub = f"{'':<11} " + " | ".join(f"{'ok':>4} {'time s':>7} {'f_n min..max':>13} {'|ft|/mu fn':>10} {'slip mm':>7}" for _ in names)
    lines = [header, sub, "-" * len(sub)]
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
            cells.append(f"{len(ok)}/{len(rs):<2} {time_s:>7} {f_lo:>6.1f}..{f_hi:<5.1f} {np.mean([r.max_friction_ratio for r in rs]):>10.2f} "
                         f"{np.mean([r.slip for r in rs]) * 1000:>7.1f}")
        lines.append(f"{person:<11} " + " | ".join(cells))
    totals = []
    for name in names:
        rs = [r for by in results[name].values() for r in by]
        totals.append(f"{sum(r.success for r in rs)}/{len(rs)} succeeded")
    lines.append("-" * len(sub))
    lines.append(f"{'all':<11} " + " | ".join(f"{t:^44}" for t in totals))
    return "\n".join(line.rstrip() for line in lines)
