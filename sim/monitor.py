"""A trial's outcome, watched step by step: the success rule of the lab's experiment, for the
headless trials (sim/procedures/trial.py) and for the live world's scripted participant.

A trial starts when lifting starts while the person still grasps the box (or when a headless
trial begins it). Success is judged by the world's own state, never by what a controller
returns: once the person has finished the path (phase "done"), the box is within
`goal_tolerance` of its start + the path's displacement and held by both plate and palm, and the
path took as long as the person's path takes. It fails when the box slipped 2 cm in the palm, the
plate or the palm lost contact for more than 0.2 s, the robot stopped in a reflex (with what in
the command caused it, when the twist jumped), the goal was not reached in 60 s, or there was no
grip in the band within 15 s; it is abandoned when the palm was taken over (the dashboard's gizmo).

The figures a trial keeps live in one array (`TrialMonitor.state`, sim/state.py) that the compiled
`monitor_update` advances after every step (the compiled world step runs it too); it says which
rule ended the trial, and the monitor words the outcome.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from sim.person.human import CARRYING, DONE, GRASPING, MANUAL, PHASE
from sim.state import Field, Flag, Scalar, allocate


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


# the monitor's state array (sim/state.py)
(
    RUNNING,
    STARTED_AT,
    ELAPSED,
    SLIP,
    F_N_LOW,
    F_N_HIGH,
    RATIO,
    NO_CONTACT_TIME,
    PALM_LOSS_TIME,
    HAS_SLIP_REFERENCE,
    HAS_CARRY_START,
    CARRY_START,
    JUMP_COUNT,
) = range(13)
SLIP_REFERENCE, PREVIOUS_TWIST, JUMPS = 13, 16, 22  # 3, 6, JUMP_HISTORY x 2
JUMP_HISTORY = 100  # steps whose command jumps a reflex report looks at
# what ended a trial (monitor_update's answer)
NONE, ABANDONED, REFLEX, PATH_DONE, TIME_LIMIT, NO_GRIP, SLIPPED, PLATE_LOST, PALM_LOST = range(9)
# TrialRules as monitor_update reads them
TIME_LIMIT_S, APPROACH_LIMIT_S, MAX_SLIP, CONTACT_FORCE, MAX_CONTACT_LOSS = range(5)
# a contact's result array (sim/physics/contact.py, _patch_kernel's `out`)
OUT_NORMAL_FORCE, OUT_TANGENTIAL, OUT_IN_CONTACT, OUT_NORMAL = 9, 10, 15, 17


class TrialMonitor:
    """The success rule applied after every step of a world (duck-typed: World)."""

    state_attribute = "state_array"  # `state` is the trial's state name, as ever
    started_at = Scalar(STARTED_AT)  # s, world time
    elapsed = Scalar(ELAPSED)  # s since the trial began
    slip = Scalar(SLIP)  # m, max slip of the box in the palm
    f_n_low = Scalar(F_N_LOW)  # N, plate normal force once let go (min, max)
    f_n_high = Scalar(F_N_HIGH)
    ratio = Scalar(RATIO)  # max |f_t| / (mu f_n)
    no_contact_time = Scalar(NO_CONTACT_TIME)  # s the plate has been off the box
    palm_loss_time = Scalar(PALM_LOSS_TIME)  # s the palm has been off the box
    previous_twist = Field(PREVIOUS_TWIST, 6)
    _jumps = Field(JUMPS, JUMP_HISTORY, 2)  # |dv| (m/s), |dw| (rad/s) of the last steps (a ring)
    _running = Flag(RUNNING)

    def __init__(self, rules: TrialRules | None = None) -> None:
        self.state_array = allocate(TrialMonitor)
        self.rules = rules or TrialRules()
        self.state = "none"
        self.participant = ""
        self._clear()

    @property
    def rules(self) -> TrialRules:
        return self._rules

    @rules.setter
    def rules(self, rules: TrialRules) -> None:
        self._rules = rules
        self.rules_vector = np.array(
            [rules.time_limit, rules.approach_limit, rules.max_slip, rules.contact_force, rules.max_contact_loss]
        )

    @property
    def state(self) -> str:
        """none, running, succeeded, failed, abandoned."""
        return self._state

    @state.setter
    def state(self, name: str) -> None:
        self._state = name
        self._running = name == "running"

    @property
    def slip_reference(self) -> np.ndarray | None:
        """The palm centre in the box frame when the grasp was let go (None before)."""
        a = self.state_array
        return a[SLIP_REFERENCE : SLIP_REFERENCE + 3] if a[HAS_SLIP_REFERENCE] else None

    @property
    def carry_start(self) -> float | None:
        """s, when the person began the path (None before)."""
        a = self.state_array
        return float(a[CARRY_START]) if a[HAS_CARRY_START] else None

    @property
    def jumps(self) -> list[tuple[float, float]]:
        """(|dv|, |dw|) of the twist command over the last steps (at most JUMP_HISTORY)."""
        count = int(self.state_array[JUMP_COUNT])
        return [tuple(row) for row in self._jumps[: min(count, JUMP_HISTORY)]]

    def _clear(self) -> None:
        running = self.state_array[RUNNING]
        self.state_array[:] = 0.0
        self.state_array[RUNNING] = running
        self.finished = False
        self.reason = ""
        self.f_n_low = math.inf
        self.box_start: np.ndarray | None = None  # m, world
        self.box_rotation_start: np.ndarray | None = None
        self.palm_start: np.ndarray | None = None  # m, the palm centre
        self.hand_start: np.ndarray | None = None  # m, the path's origin

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
        box, human = world.box, world.human
        event = monitor_update(
            self.state_array,
            self.rules_vector,
            world.time,
            world.config.dt,
            human.state[PHASE],
            world.twist_command,
            human.grasp_weight,
            world.error is not None,
            box.position,
            box.rotation,
            human.position,
            world.plate_out,
            world.palm_out,
            world.params.mu,
        )
        self.conclude(event, world)

    def conclude(self, event: int, world) -> None:
        """Word the outcome monitor_update found (NONE: the trial goes on)."""
        if event == NONE:
            return
        rules = self.rules
        if event == ABANDONED:
            self._finish("abandoned: the palm was taken over (no scripted result)", "abandoned")
        elif event == SLIPPED:
            self._finish(f"dropped: the box slipped {self.slip * 100:.1f} cm in the palm")
        elif event == PLATE_LOST:
            self._finish(f"dropped: the robot lost contact for more than {rules.max_contact_loss:g} s")
        elif event == PALM_LOST:
            self._finish(f"dropped: the person's palm lost the box for more than {rules.max_contact_loss:g} s")
        elif event == REFLEX:
            self._finish(self._reflex(world.error, world.config.dt))
        elif event == PATH_DONE:
            self._finish(self._judge(world))
        elif event == TIME_LIMIT:
            self._finish(f"time limit: goal not reached in {rules.time_limit:g} s")
        elif event == NO_GRIP:
            self._finish(f"no grip: the robot did not press the box into the band in {rules.approach_limit:g} s")

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
        error = float(np.linalg.norm(world.box.position - goal))
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
            hint = (
                f"; your twist jumps by up to {dv:.3f} m/s ({dv / dt:.0f} m/s^2), {dw:.3f} rad/s ({dw / dt:.0f} rad/s^2) "
                "between steps: low-pass F_ext (step 0) and limit the rate (at most a_max dt, dw_max dt per step)"
            )
        return f"robot reflex: {error}{hint}"

    def _finish(self, reason: str, state: str | None = None) -> None:
        if not self.finished:
            self.finished = True
            self.reason = reason
            self.state = state or ("succeeded" if reason == "" else "failed")

    def outcome(self) -> TrialOutcome:
        return TrialOutcome(
            state=self.state,
            participant=self.participant,
            duration=float(self.elapsed),
            f_n_min=float(self.f_n_low) if np.isfinite(self.f_n_low) else 0.0,
            f_n_max=float(self.f_n_high),
            max_friction_ratio=float(self.ratio),
            slip=float(self.slip),
            reason=self.reason,
        )


@njit(cache=True)
def _norm3(x, y, z):
    return math.sqrt(x * x + y * y + z * z)


@njit(cache=True)
def monitor_update(
    m,
    rules,
    time,
    dt,
    phase,
    twist,
    grasp_weight,
    has_error,
    box_position,
    box_rotation,
    palm_position,
    plate_out,
    palm_out,
    mu,
):
    """One step of the success rule on the monitor's state `m` (module docstring): the command's
    jumps, the carry's start, and once the grasp is let go the slip, contact and force figures;
    returns what ended the trial (the first rule broken), NONE while it goes on."""
    if m[RUNNING] == 0.0:
        return NONE
    m[ELAPSED] = time - m[STARTED_AT]
    if phase == MANUAL:
        m[RUNNING] = 0.0
        return ABANDONED
    previous = m[PREVIOUS_TWIST : PREVIOUS_TWIST + 6]
    row = JUMPS + 2 * (int(m[JUMP_COUNT]) % JUMP_HISTORY)
    m[row] = _norm3(twist[0] - previous[0], twist[1] - previous[1], twist[2] - previous[2])
    m[row + 1] = _norm3(twist[3] - previous[3], twist[4] - previous[4], twist[5] - previous[5])
    m[JUMP_COUNT] += 1.0
    previous[:] = twist
    if m[HAS_CARRY_START] == 0.0 and phase == CARRYING:
        m[HAS_CARRY_START], m[CARRY_START] = 1.0, time
    event = NONE
    if grasp_weight <= 0.0:
        event = _watch_hold(m, rules, dt, box_position, box_rotation, palm_position, plate_out, palm_out, mu)
    if event == NONE:
        elapsed = m[ELAPSED]
        if has_error:
            event = REFLEX
        elif phase == DONE:
            event = PATH_DONE
        elif elapsed >= rules[TIME_LIMIT_S]:
            event = TIME_LIMIT
        elif phase == GRASPING and elapsed >= rules[APPROACH_LIMIT_S]:
            event = NO_GRIP
    if event != NONE:
        m[RUNNING] = 0.0
    return event


@njit(cache=True)
def _watch_hold(m, rules, dt, box_position, box_rotation, palm_position, plate_out, palm_out, mu):
    # slip = how far the palm centre slid over the box face since the grasp was let go:
    # the palm centre in the box frame, minus its component along the face normal
    palm_in_box = box_rotation.T @ (palm_position - box_position)
    reference = m[SLIP_REFERENCE : SLIP_REFERENCE + 3]
    if m[HAS_SLIP_REFERENCE] == 0.0:
        reference[:] = palm_in_box
        m[HAS_SLIP_REFERENCE] = 1.0
    moved = palm_in_box - reference
    if palm_out[OUT_IN_CONTACT] > 0.0:
        normal_box = box_rotation.T @ palm_out[OUT_NORMAL : OUT_NORMAL + 3]
        moved = moved - (moved[0] * normal_box[0] + moved[1] * normal_box[1] + moved[2] * normal_box[2]) * normal_box
    m[SLIP] = max(m[SLIP], _norm3(moved[0], moved[1], moved[2]))
    f_n = plate_out[OUT_NORMAL_FORCE]
    m[F_N_LOW], m[F_N_HIGH] = min(m[F_N_LOW], f_n), max(m[F_N_HIGH], f_n)
    if f_n > 1e-9:
        t = plate_out[OUT_TANGENTIAL : OUT_TANGENTIAL + 3]
        m[RATIO] = max(m[RATIO], _norm3(t[0], t[1], t[2]) / (mu * f_n))
    m[NO_CONTACT_TIME] = m[NO_CONTACT_TIME] + dt if f_n < rules[CONTACT_FORCE] else 0.0
    palm = palm_out[OUT_NORMAL_FORCE]
    m[PALM_LOSS_TIME] = m[PALM_LOSS_TIME] + dt if palm < rules[CONTACT_FORCE] else 0.0
    if m[SLIP] > rules[MAX_SLIP]:
        return SLIPPED
    if m[NO_CONTACT_TIME] > rules[MAX_CONTACT_LOSS]:
        return PLATE_LOST
    if m[PALM_LOSS_TIME] > rules[MAX_CONTACT_LOSS]:
        return PALM_LOST
    return NONE
