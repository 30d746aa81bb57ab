"""The lab's experiment (Table 1 of the handout), headless and faster than real time.

A trial (DESIGN.md section 8): the robot at the start pose; the person holds the box grasped a
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

from collections import deque
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import asdict, dataclass, field
from typing import Callable

import numpy as np

from sim.controllers.interface import Controller, LiftingParams
from sim.person.human import PARTICIPANTS, TABLE_1, Participant
from sim.controllers.sp import SPController
from sim.spatial import norm3
from sim.world import World, WorldConfig


@dataclass(frozen=True)
class TrialRules:
    """The success rule (SI units)."""

    force: float = 10.0  # N, f_n_min given to start_cooperative_lifting
    time_limit: float = 60.0  # s to reach the goal
    approach_limit: float = 15.0  # s for the robot to get a grip in the band
    max_slip: float = 0.02  # m, box relative to the palm (tangential)
    contact_force: float = 0.5  # N, plate (palm) normal force below this = no contact
    max_contact_loss: float = 0.2  # s
    goal_tolerance: float = 0.03  # m, box centre from start + the path's displacement at the end


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
        self.finished = False
        self.reason = ""
        self.slip = 0.0
        self.f_n_low = np.inf
        self.f_n_high = 0.0
        self.ratio = 0.0
        self.no_contact_time = 0.0
        self.palm_loss_time = 0.0
        self.slip_reference: np.ndarray | None = None
        self.steps = 0
        self.box_start = self.world.box.position.copy()
        self.hand_start = self.world.human.start.copy()  # the path's origin (a test may move it)
        self.carry_start: float | None = None  # s, when the person began the path
        self.previous_twist = np.zeros(6)
        self.jumps: deque[tuple[float, float]] = deque(maxlen=100)  # |dv| m/s, |dw| rad/s per step

    def step(self) -> bool:
        """Advance one control period; False once the trial is over."""
        if self.finished:
            return False
        world = self.world
        world.step()
        self.steps += 1
        human = world.human
        twist = world.twist_command
        self.jumps.append((norm3(twist[:3] - self.previous_twist[:3]), norm3(twist[3:] - self.previous_twist[3:])))
        self.previous_twist = twist.copy()
        if self.carry_start is None and human.phase == "carrying":
            self.carry_start = world.time
        if human.holding_by_contact:
            self._monitor_hold()
        if world.error:
            self._finish(self._reflex(world.error))
        elif human.phase == "done":
            self._finish(self._judge())
        elif world.time >= self.rules.time_limit:
            self._finish(f"time limit: goal not reached in {self.rules.time_limit:g} s")
        elif human.phase == "grasping" and world.time >= self.rules.approach_limit:
            self._finish(f"no grip: the robot did not press the box into the band in {self.rules.approach_limit:g} s")
        return not self.finished

    def _monitor_hold(self) -> None:
        """Slip in the palm, robot contact, force figures (once the grasp is let go)."""
        world, rules = self.world, self.rules
        human = world.human
        # slip = how far the palm centre slid over the box face since the grasp was let go:
        # the palm centre in the box frame, minus its component along the face normal
        box = world.box
        palm_in_box = box.rotation.T @ (human.position - box.position)
        if self.slip_reference is None:
            self.slip_reference = palm_in_box
        moved = palm_in_box - self.slip_reference
        normal_box = box.rotation.T @ world.palm_state.normal_world if world.palm_state.points_in_contact else None
        if normal_box is not None:
            moved = moved - (moved @ normal_box) * normal_box
        self.slip = max(self.slip, norm3(moved))
        plate = world.plate_state
        f_n = plate.normal_force
        self.f_n_low, self.f_n_high = min(self.f_n_low, f_n), max(self.f_n_high, f_n)
        if f_n > 1e-9:
            self.ratio = max(self.ratio, norm3(plate.tangential_force) / (world.params.mu * f_n))
        self.no_contact_time = self.no_contact_time + world.config.dt if f_n < rules.contact_force else 0.0
        palm = world.palm_state.normal_force
        self.palm_loss_time = self.palm_loss_time + world.config.dt if palm < rules.contact_force else 0.0
        if self.slip > rules.max_slip:
            self._finish(f"dropped: the box slipped {self.slip * 100:.1f} cm in the palm")
        elif self.no_contact_time > rules.max_contact_loss:
            self._finish(f"dropped: the robot lost contact for more than {rules.max_contact_loss:g} s")
        elif self.palm_loss_time > rules.max_contact_loss:
            self._finish(f"dropped: the person's palm lost the box for more than {rules.max_contact_loss:g} s")

    def _judge(self) -> str:
        """The person finished the path: was the box carried there? ("" = yes, else why not)."""
        world, rules = self.world, self.rules
        path = world.human.path
        goal = self.box_start + (world.human.start - self.hand_start) + path.goal  # where the person's path ends
        error = norm3(world.box.position - goal)
        if self.carry_start is None or self.slip_reference is None:
            return "not carried: the person never carried the box by the palm"
        if world.time - self.carry_start < path.duration - 1e-6:
            return f"not carried: the path ended after {world.time - self.carry_start:.2f} s, it takes {path.duration:.2f} s"
        if error > rules.goal_tolerance:
            return f"not carried: the box ended {error * 100:.1f} cm from the goal (tolerance {rules.goal_tolerance * 100:g} cm)"
        if world.plate_state.normal_force < rules.contact_force or world.palm_state.normal_force < rules.contact_force:
            return "not carried: at the goal the box is not held between plate and palm"
        return ""

    def _reflex(self, error: str) -> str:
        """The robot's error, and what in the controller's twist caused it (a reflex on a jump)."""
        if error.startswith("controller error"):
            return error
        dw = max((w for _, w in self.jumps), default=0.0)
        dv = max((v for v, _ in self.jumps), default=0.0)
        dt = self.world.config.dt
        hint = ""
        if dv / dt > 5.0 or dw / dt > 10.0:  # m/s^2, rad/s^2: well above a smooth command's
            hint = (f"; your twist jumps by up to {dv:.3f} m/s ({dv / dt:.0f} m/s^2), {dw:.3f} rad/s ({dw / dt:.0f} rad/s^2) "
                    "between steps: low-pass F_ext (step 0) and limit the rate (at most a_max dt, dw_max dt per step)")
        return f"robot reflex: {error}{hint}"

    def _finish(self, reason: str) -> None:
        if not self.finished:
            self.finished = True
            self.reason = reason

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
            f_n_min=float(self.f_n_low) if np.isfinite(self.f_n_low) else 0.0,
            f_n_max=float(self.f_n_high),
            max_friction_ratio=float(self.ratio),
            slip=float(self.slip),
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
    controller = controller_factory()
    try:
        return Trial(person, seed, controller, rules=rules, index=index, attempt=attempt).run()
    finally:
        getattr(controller, "close", lambda: None)()  # a sandboxed plug-in's process ends with its trial


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
