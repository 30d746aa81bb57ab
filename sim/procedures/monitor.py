"""A trial's outcome, watched step by step: the success rule of the lab's experiment, for the
headless trials (sim/procedures/experiment.py) and for the live world's scripted participant.

A trial starts when lifting starts while the person still grasps the box (or when a headless
trial begins it) and ends: succeeded when the person has carried the box and held it (phase
"done"); failed when the box slipped 2 cm in the palm, the robot lost contact for more than
0.2 s, the robot stopped in a reflex, the goal was not reached in 60 s, or there was no grip in
the band within 15 s; abandoned when the palm was taken over (the dashboard's gizmo).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sim.spatial import norm3


@dataclass(frozen=True)
class TrialRules:
    """The success rule (SI units)."""

    force: float = 10.0  # N, f_n_min given to start_cooperative_lifting
    time_limit: float = 60.0  # s to reach the goal
    approach_limit: float = 15.0  # s for the robot to get a grip in the band
    max_slip: float = 0.02  # m, box relative to the palm (tangential)
    contact_force: float = 0.5  # N, plate normal force below this = no contact
    max_contact_loss: float = 0.2  # s


@dataclass
class TrialOutcome:
    """What the live world publishes about its trial (fixed fields: it is shared memory)."""

    state: str = "none"  # none, running, succeeded, failed, abandoned
    participant: str = ""
    duration: float = 0.0  # s since lifting started
    f_n_min: float = 0.0  # N, plate normal force once the person let go (min, max)
    f_n_max: float = 0.0
    max_friction_ratio: float = 0.0  # max |f_t| / (mu f_n), mu = the controller's mu
    slip: float = 0.0  # m, max slip of the box in the palm
    reason: str = ""  # why it failed ("" on success)


class TrialMonitor:
    """The success rule applied after every step of a world (duck-typed: World)."""

    def __init__(self, rules: TrialRules | None = None) -> None:
        self.rules = rules or TrialRules()
        self.state = "none"
        self.started_at = 0.0
        self.participant = ""
        self._clear()

    def _clear(self) -> None:
        self.finished = False
        self.reason = ""
        self.elapsed = 0.0
        self.slip = 0.0
        self.f_n_low = np.inf
        self.f_n_high = 0.0
        self.ratio = 0.0
        self.no_contact_time = 0.0
        self.slip_reference: np.ndarray | None = None

    def begin(self, time: float, participant: str) -> None:
        """A trial from now (s, world time)."""
        self._clear()
        self.state, self.started_at, self.participant = "running", time, participant

    def update(self, world) -> None:
        """After a step: slip, contact, force figures once the grasp is let go; then the end rules."""
        if self.state != "running":
            return
        rules, human = self.rules, world.human
        self.elapsed = world.time - self.started_at
        if human.phase == "manual":
            self._finish("abandoned: the palm was taken over (no scripted result)", "abandoned")
            return
        if human.holding_by_contact:
            self._watch_hold(world)
        if world.error:
            self._finish(f"robot reflex: {world.error}")
        elif human.phase == "done":
            self._finish("")
        elif self.elapsed >= rules.time_limit:
            self._finish(f"time limit: goal not reached in {rules.time_limit:g} s")
        elif human.phase == "grasping" and self.elapsed >= rules.approach_limit:
            self._finish(f"no grip: the robot did not press the box into the band in {rules.approach_limit:g} s")

    def _watch_hold(self, world) -> None:
        rules, human, box = self.rules, world.human, world.box
        # slip = how far the palm centre slid over the box face since the grasp was let go:
        # the palm centre in the box frame, minus its component along the face normal
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
        if self.slip > rules.max_slip:
            self._finish(f"dropped: the box slipped {self.slip * 100:.1f} cm in the palm")
        elif self.no_contact_time > rules.max_contact_loss:
            self._finish(f"dropped: the robot lost contact for more than {rules.max_contact_loss:g} s")

    def _finish(self, reason: str, state: str | None = None) -> None:
        if not self.finished:
            self.finished = True
            self.reason = reason
            self.state = state or ("succeeded" if reason == "" else "failed")

    def outcome(self) -> TrialOutcome:
        return TrialOutcome(
            state=self.state, participant=self.participant, duration=float(self.elapsed),
            f_n_min=float(self.f_n_low) if np.isfinite(self.f_n_low) else 0.0, f_n_max=float(self.f_n_high),
            max_friction_ratio=float(self.ratio), slip=float(self.slip), reason=self.reason,
        )
