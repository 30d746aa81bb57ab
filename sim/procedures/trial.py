"""One trial of the lab's experiment (Table 1 of the handout), headless and faster than real time.

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

from collections.abc import Callable
from dataclasses import asdict, dataclass, field, replace
from typing import Any

import numpy as np

from sim.controllers.interface import Controller, LiftingParams
from sim.controllers.sp import SPController
from sim.monitor import TrialRules
from sim.person.participants import Participant
from sim.recording.trial import TrialObserver, TrialOutputs
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


def run_trial(
    index: int,
    person: Participant,
    attempt: int,
    seed: int,
    rules: TrialRules = TrialRules(),
    controller_factory: Callable[[], Controller] = SPController,
    setup: Setup = Setup(),
    outputs: TrialOutputs | None = None,
) -> TrialResult:
    """outputs: a sim.recording.trial.TrialOutputs (recording and figure of the trial) or None."""
    trial = make_trial(index, person, attempt, seed, rules, controller_factory, setup)
    try:
        if outputs is None or not outputs.wanted:
            return trial.run()
        observer = trial.observer = TrialObserver(trial, outputs)
        result = trial.run()
        result.files = observer.finish(result)
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
