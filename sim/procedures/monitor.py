"""A trial's outcome, watched step by step: the success rule of the lab's experiment, for the
headless trials (sim/procedures/experiment.py) and for the live world's scripted participant.

A trial starts when lifting starts while the person still grasps the box (or when a headless
trial begins it). Success is judged by the world's own state, never by what a controller
returns: once the person has finished the path (phase "done"), the box is within
`goal_tolerance` of its start + the path's displacement and held by both plate and palm, and the
path took as long as the person's path takes. It fails when the box slipped 2 cm in the palm, the
plate or the palm lost contact for more than 0.2 s, the robot stopped in a reflex (with what in
the command caused it, when the twist jumped), the goal was not reached in 60 s, or there was no
grip in the band within 15 s; it is abandoned when the palm was taken over (the dashboard's gizmo).
"""
from __future__ import annotations

from collections import deque
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
    contact_force: float = 0.5  # N, plate (palm) normal force below this = no contact
    max_contact_loss: float = 0.2  # s
    goal_tolerance: float = 0.03  # m, box centre from start + the path's displacement at the end
    jump_acceleration: float = 5.0  # m/s^2 between two commands: above, a reflex report names the jump
    jump_angular_acceleration: float = 10.0  # rad/s^2, the same for the angular part


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
        self.palm_loss_time = 0.0
        self.slip_reference: np.ndarray | None = None
        self.carry_start: float | None = None  # s, when the person began the path
        self.box_start: np.ndarray | None = None  # m, world
        self.box_rotation_start: np.ndarray | None = None
        self.palm_start: np.ndarray | None = None  # m, the palm centre
        self.hand_start: np.ndarray | None = None  # m, the path's origin
        self.previous_twist = np.zeros(6)
        self.jumps: deque[tuple[float, float]] = deque(maxlen=100)  # |dv| (m/s), |dw| (rad/s) of the last steps

    def begin(self, time: float, participant: str, world=None) -> None:
        """A trial from now (s, world time); `world` fixes where the box and the path start."""
        self._clear()
        self.state, self.started_at, self.participant = "running", time, participant
        if world is not None:
            self.box_start, self.box_rotation_start = world.box.position.copy(), world.box.rotation.copy()
            self.palm_start, self.hand_start = world.human.position.copy(), world.human.start.copy()

    def update(self, world) -> None:
        """After a step: slip, contact, force figures once the grasp is let go; then the end rules."""
        if self.state != "running":
            return
        rules, human = self.rules, world.human
        self.elapsed = world.time - self.started_at
        if human.phase == "manual":
            self._finish("abandoned: the palm was taken over (no scripted result)", "abandoned")
            return
        twist = world.twist_command
        self.jumps.append((norm3(twist[:3] - self.previous_twist[:3]), norm3(twist[3:] - self.previous_twist[3:])))
        self.previous_twist = twist.copy()
        if self.carry_start is None and human.phase == "carrying":
            self.carry_start = world.time
        if human.holding_by_contact:
            self._watch_hold(world)
        if world.error:
            self._finish(self._reflex(world.error, world.config.dt))
        elif human.phase == "done":
            self._finish(self._judge(world))
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
        palm = world.palm_state.normal_force
        self.palm_loss_time = self.palm_loss_time + world.config.dt if palm < rules.contact_force else 0.0
        if self.slip > rules.max_slip:
            self._finish(f"dropped: the box slipped {self.slip * 100:.1f} cm in the palm")
        elif self.no_contact_time > rules.max_contact_loss:
            self._finish(f"dropped: the robot lost contact for more than {rules.max_contact_loss:g} s")
        elif self.palm_loss_time > rules.max_contact_loss:
            self._finish(f"dropped: the person's palm lost the box for more than {rules.max_contact_loss:g} s")

    def _judge(self, world) -> str:
        """The person finished the path: was the box carried there? ("" = yes, else why not)."""
        rules, path = self.rules, world.human.path
        if self.carry_start is None or self.slip_reference is None or self.box_start is None:
            return "not carried: the person never carried the box by the palm"
        if world.time - self.carry_start < path.duration - 1e-6:
            return f"not carried: the path ended after {world.time - self.carry_start:.2f} s, it takes {path.duration:.2f} s"
        # where the person's path takes the box: the palm to the path's end, the box turned with it
        #   goal = p_palm,0 + (hand shift) + path goal + R_box R_box,0^T (p_box,0 - p_palm,0)
        assert self.box_rotation_start is not None  # set when the person let go (carry_start)
        turn = world.box.rotation @ self.box_rotation_start.T
        palm_goal = self.palm_start + (world.human.start - self.hand_start) + path.goal
        goal = palm_goal + turn @ (self.box_start - self.palm_start)
        error = norm3(world.box.position - goal)
        if error > rules.goal_tolerance:
            return f"not carried: the box ended {error * 100:.1f} cm from the goal (tolerance {rules.goal_tolerance * 100:g} cm)"
        if world.plate_state.normal_force < rules.contact_force or world.palm_state.normal_force < rules.contact_force:
            return "not carried: at the goal the box is not held between plate and palm"
        return ""

    def _reflex(self, error: str, dt: float) -> str:
        """The robot's error, and what in the controller's twist caused it (a reflex on a jump)."""
        if error.startswith("controller error"):
            return error
        dv = max((v for v, _ in self.jumps), default=0.0)
        dw = max((w for _, w in self.jumps), default=0.0)
        hint = ""
        if dv / dt > self.rules.jump_acceleration or dw / dt > self.rules.jump_angular_acceleration:
            hint = (f"; your twist jumps by up to {dv:.3f} m/s ({dv / dt:.0f} m/s^2), {dw:.3f} rad/s ({dw / dt:.0f} rad/s^2) "
                    "between steps: low-pass F_ext (step 0) and limit the rate (at most a_max dt, dw_max dt per step)")
        return f"robot reflex: {error}{hint}"

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
