"""Situations of a trial where SP and a follower part ways (the grader's robustness items): the
person stops mid-carry and holds the box still, lets the robot take more of the weight, turns it.
Each is a perturbation called after every step of a Trial (sim/procedures/trial.py); it
changes only what the person does (the hand's path, the wrist's aim), never the robot or the box.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from sim.spatial import rotation_exp

UP = np.array([0.0, 0.0, 1.0])


@dataclass
class MidCarryStop:
    """Somewhere in the middle of the carry (a fraction drawn from `rng` in [0.3, 0.7] of it) the
    person stops: holds the box still for `hold` s (SP keeps its share of the weight; a follower
    creeps under it), then lets the robot take more of it (the hand sinks `sink` m in `sink_time`
    s while the box should stay), then turns the box `turn` rad about the carry direction in
    `turn_time` s (a moment at the plate SP complies with), then carries on."""

    rng: np.random.Generator
    hold: float = 2.0  # s
    sink: float = 0.01  # m
    sink_time: float = 0.5  # s
    turn: float = np.radians(8.0)  # rad
    turn_time: float = 0.5  # s
    paused: float = field(default=0.0, init=False)  # s stopped so far
    stop_at: float | None = field(default=None, init=False)  # s into the carry

    @property
    def duration(self) -> float:
        return self.hold + self.sink_time + self.turn_time

    def __call__(self, trial) -> None:
        human, dt = trial.world.human, trial.world.config.dt
        if human.phase != "carrying" or self.paused >= self.duration:
            return
        if self.stop_at is None:
            (_, lift), (_, carry), _ = human.path.segments
            self.stop_at = lift + float(self.rng.uniform(0.3, 0.7)) * carry
        if human.phase_time < self.stop_at:
            return
        human.phase_time -= dt  # the path stands still
        self.paused += dt
        if self.hold <= self.paused < self.hold + self.sink_time:
            human.start = human.start - UP * (self.sink / self.sink_time * dt)
        elif self.paused >= self.hold + self.sink_time and human.box_level is not None:
            axis = np.asarray(human.path_spec.carry_direction, float)
            human.box_level = (
                rotation_exp(axis / np.linalg.norm(axis) * (self.turn / self.turn_time * dt)) @ human.box_level
            )
