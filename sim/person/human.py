"""The virtual human: a palm that holds, squeezes and carries the box.

The palm is a kinematic patch (the person's arm is much stiffer than the box contact). Its pose is
    p_palm = p_path(t) + s n_palm + tremor(t)
with p_path the hand path (or a target set directly), n_palm the palm's push direction and s the
squeeze offset the person regulates from the force felt in the palm (an admittance with a weak
spring back to the path, so the person does not drift):
    s' = k_f (F_target - F_palm) - k_p s,   F_target = max(F_squeeze, r |f_t,palm|)
(people squeeze harder as the load in their hand grows: grip-load coupling).
At the trial's start the person also GRASPS the box (a 6-D spring-damper between the box and the
hand, so the box cannot fall yet) and lets go of the grasp, gently, once the robot's grip is in
the band; from then on the box is held only by the two contacts.

The person's state lives in one array (`VirtualHuman.state`, sim/state.py) that `human_step` and
`hand_wrench` advance and read: the compiled world step (sim/compiled_step.py) runs the same two.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from sim import signals, spatial
from sim.person.participants import PARTICIPANTS, Participant
from sim.physics.contact import BoxPose
from sim.state import Field, Flag, Scalar, allocate


@dataclass(frozen=True)
class PickAndPlace:
    """The hand path of a trial, relative to where the hand starts (m, s)."""

    lift: float = 0.20
    carry: float = 0.30
    lower: float = 0.20
    hold: float = 1.0
    carry_direction: tuple[float, float, float] = (-1.0, 0.0, 0.0)  # base frame


class HandPath:
    """Minimum-jerk pick-and-place: lift, carry, lower, hold."""

    def __init__(self, path: PickAndPlace, peak_speed: float) -> None:
        up = np.array([0.0, 0.0, 1.0])
        carry = np.asarray(path.carry_direction, float)
        carry = carry / np.linalg.norm(carry)
        moves = [up * path.lift, carry * path.carry, -up * path.lower]
        self.segments = [(m, 1.875 * float(np.linalg.norm(m)) / peak_speed) for m in moves]
        self.hold = path.hold
        self.duration = sum(t for _, t in self.segments) + path.hold
        self.goal = sum(moves, np.zeros(3))
        self.moves = np.array(moves)  # (3, 3) m, and each one's duration (s): what human_step reads
        self.durations = np.array([t for _, t in self.segments])

    def offset(self, t: float) -> np.ndarray:
        """Hand displacement (m) from the start at time t (s) since the carry began."""
        return path_offset(self.moves, self.durations, t)


@njit(cache=True)
def path_offset(moves, durations, t):
    """The minimum-jerk segments' displacement (m) at t (s): each segment in turn."""
    offset = np.zeros(3)
    for i in range(moves.shape[0]):
        if t <= 0.0:
            break
        offset += moves[i] * minimum_jerk(t / durations[i])
        t -= durations[i]
    return offset


@dataclass(frozen=True)
class HumanParams:
    grip_dwell: float = 0.3  # s the robot's grip must stay in the band before letting go
    feel_time_constant: float = 0.1  # s, a person feels the grip force smoothed
    release_time: float = 0.3  # s to let go of the grasp (grasp weight 1 -> 0)
    settle_time: float = 0.5  # s between letting go and starting to move
    k_f: float = 0.01  # (m/s)/N, squeeze admittance
    grip_load_ratio: float = 1.0  # squeeze >= this x the tangential load felt in the palm
    k_p: float = 2.0  # 1/s, pull of the squeeze offset back to the path
    v_squeeze_max: float = 0.2  # m/s
    grasp_stiffness: float = 5000.0  # N/m
    grasp_damping: float = 140.0  # N s/m
    grasp_rot_stiffness: float = 50.0  # Nm/rad
    grasp_rot_damping: float = 1.2  # Nm s/rad
    wrist_stiffness: float = 20.0  # Nm/rad, the wrist keeps the box at the orientation it had when let go
    wrist_damping: float = 0.5  # Nm s/rad
    hand_lever: float = 0.15  # m, |wrist moment| <= hand_lever * palm force (fingers hooked on the edge)
    manual_speed: float = 0.5  # m/s, palm speed toward a directly set target
    manual_gain: float = 10.0  # 1/s


PHASES = ("grasping", "releasing", "settling", "carrying", "holding", "done", "manual")
GRASPING, RELEASING, SETTLING, CARRYING, HOLDING, DONE, MANUAL = range(len(PHASES))

# plain code of sim/signals.py and sim/spatial.py, compiled here for the kernels
minimum_jerk = njit(cache=True)(signals.minimum_jerk)
exp3 = njit(cache=True)(spatial.exp3)
log3 = njit(cache=True)(spatial.log3)

# the person's state array (sim/state.py)
(
    TIME,
    PHASE_TIME,
    SQUEEZE,
    GRIP_TIME,
    FELT_GRIP,
    LETTING_GO,
    GRASP_WEIGHT,
    PHASE,
    HAS_LEVEL,
    HAS_GRASP,
    SQUEEZE_FORCE,
    TREMOR_AMPLITUDE,
    TILT,
    HOLD,
    PATH_DURATION,
) = range(15)
HAND, TARGET, POSITION, VELOCITY, ANGULAR_VELOCITY, START, GRASP_POSITION = 15, 18, 21, 24, 27, 30, 33
TARGET_ROTATION, ROTATION, BOX_LEVEL, GRASP_ROTATION = 36, 45, 54, 63
TREMOR_PHASE, TREMOR_FREQUENCY, MOVES, DURATIONS = 72, 74, 76, 85  # 2, 2, 9, 3
# HumanParams as the kernels read them (field order), then the carry direction (unit, 3)
(
    GRIP_DWELL,
    FEEL_TIME_CONSTANT,
    RELEASE_TIME,
    SETTLE_TIME,
    K_F,
    GRIP_LOAD_RATIO,
    K_P,
    V_SQUEEZE_MAX,
    GRASP_STIFFNESS,
    GRASP_DAMPING,
    GRASP_ROT_STIFFNESS,
    GRASP_ROT_DAMPING,
    WRIST_STIFFNESS,
    WRIST_DAMPING,
    HAND_LEVER,
    MANUAL_SPEED,
    MANUAL_GAIN,
    CARRY_AXIS,
) = range(18)


class VirtualHuman:
    """Scripted (a participant following a pick-and-place path) or manual (target set directly).

    Attributes are views of `self.state` (sim/state.py); `step` and `hand_wrench` run the compiled
    `human_step` and `hand_wrench` below."""

    PHASES = PHASES

    time = Scalar(TIME)  # s since reset
    phase_time = Scalar(PHASE_TIME)  # s in the current phase
    squeeze = Scalar(SQUEEZE)  # s (m), the squeeze offset along the palm normal
    grip_time = Scalar(GRIP_TIME)  # s the robot's grip has been in the band
    felt_grip = Scalar(FELT_GRIP)  # N, the robot's push as the person feels it (low-passed)
    letting_go = Flag(LETTING_GO)
    grasp_weight = Scalar(GRASP_WEIGHT)  # 1 grasped .. 0 let go
    hand = Field(HAND, 3)  # hand position without squeeze and tremor (m)
    target = Field(TARGET, 3)  # where the hand is heading (manual mode)
    target_rotation = Field(TARGET_ROTATION, 3, 3)
    position = Field(POSITION, 3)  # palm centre (m)
    velocity = Field(VELOCITY, 3)
    angular_velocity = Field(ANGULAR_VELOCITY, 3)
    rotation = Field(ROTATION, 3, 3)  # palm -> world; its z is the push direction
    start = Field(START, 3)  # the path's origin (m)
    tremor_phase = Field(TREMOR_PHASE, 2)  # rad
    tremor_freq = Field(TREMOR_FREQUENCY, 2)  # Hz
    path_moves = Field(MOVES, 3, 3)  # m, the hand path's segments (HandPath.moves)
    path_durations = Field(DURATIONS, 3)  # s

    def __init__(
        self,
        position: np.ndarray,
        rotation: np.ndarray,
        participant: Participant = PARTICIPANTS["calm"],
        path: PickAndPlace = PickAndPlace(),
        params: HumanParams = HumanParams(),
        rng: np.random.Generator | None = None,
    ) -> None:
        self.state = allocate(VirtualHuman)
        self.params = params
        axis = np.asarray(path.carry_direction, float)
        self.constants = np.concatenate(
            ([float(getattr(params, f)) for f in HumanParams.__dataclass_fields__], axis / np.linalg.norm(axis))
        )
        self.path_spec = path
        self.rotation = np.array(rotation, float)
        self.start = np.array(position, float)
        self.rng = rng or np.random.default_rng(0)
        self.set_participant(participant)
        self.reset()

    # --- set-up -----------------------------------------------------------------------------
    def set_participant(self, participant: Participant) -> None:
        self.participant = participant
        self.path = HandPath(self.path_spec, participant.peak_speed)
        self.tremor_phase = self.rng.uniform(0.0, 2.0 * math.pi, 2)
        self.tremor_freq = participant.tremor_frequency * self.rng.uniform(0.9, 1.1, 2)
        s = self.state
        s[SQUEEZE_FORCE], s[TREMOR_AMPLITUDE], s[TILT] = (
            participant.squeeze_force,
            participant.tremor_amplitude,
            participant.tilt,
        )
        self.path_moves, self.path_durations = self.path.moves, self.path.durations
        s[HOLD], s[PATH_DURATION] = self.path.hold, self.path.duration

    def reset(self) -> None:
        self.time = 0.0
        self.hand = self.start
        self.target = self.start
        self.target_rotation = self.rotation
        self.position = self.start
        self.velocity = 0.0
        self.angular_velocity = 0.0
        self.squeeze = 0.0
        self.phase = "grasping"
        self.phase_time = 0.0
        self.grip_time = 0.0
        self.felt_grip = 0.0
        self.letting_go = False
        self.box_level = None  # box orientation the person keeps once let go
        self.grasp_weight = 1.0
        self.grasp_offset = None  # box pose in the palm frame

    @property
    def phase(self) -> str:
        return PHASES[int(self.state[PHASE])]

    @phase.setter
    def phase(self, name: str) -> None:
        self.state[PHASE] = PHASES.index(name)

    @property
    def box_level(self) -> np.ndarray | None:
        """The box orientation the wrist keeps once let go (None before)."""
        return self.state[BOX_LEVEL : BOX_LEVEL + 9].reshape(3, 3) if self.state[HAS_LEVEL] else None

    @box_level.setter
    def box_level(self, rotation: np.ndarray | None) -> None:
        self.state[HAS_LEVEL] = rotation is not None
        if rotation is not None:
            self.state[BOX_LEVEL : BOX_LEVEL + 9] = np.asarray(rotation, float).ravel()

    @property
    def grasp_offset(self) -> tuple[np.ndarray, np.ndarray] | None:
        """(box position, box rotation) in the palm frame where the box was grasped (None before)."""
        s = self.state
        if not s[HAS_GRASP]:
            return None
        return s[GRASP_POSITION : GRASP_POSITION + 3], s[GRASP_ROTATION : GRASP_ROTATION + 9].reshape(3, 3)

    @grasp_offset.setter
    def grasp_offset(self, offset: tuple[np.ndarray, np.ndarray] | None) -> None:
        self.state[HAS_GRASP] = offset is not None
        if offset is not None:
            self.state[GRASP_POSITION : GRASP_POSITION + 3] = offset[0]
            self.state[GRASP_ROTATION : GRASP_ROTATION + 9] = np.asarray(offset[1], float).ravel()

    def grasp(self, box: BoxPose) -> None:
        """Take hold of the box where it is now (it cannot fall while grasped)."""
        self.grasp_offset = (self.rotation.T @ (box.position - self.position), self.rotation.T @ box.rotation)
        self.grasp_weight = 1.0
        self.letting_go = False

    def release(self) -> None:
        """Let go of the grasp (over release_time) and keep only pushing with the palm."""
        self.letting_go = True
        if self.phase == "grasping":
            self._enter("releasing")

    def set_manual(self) -> None:
        """Hand the palm to a person (the dashboard's gizmo): it follows set_target."""
        self.target = self.hand
        self.target_rotation = self.rotation
        self._enter("manual")

    def set_target(self, position: np.ndarray, rotation: np.ndarray | None = None) -> None:
        """Palm target (m, world; rotation palm -> world), followed at a limited speed."""
        position = np.asarray(position, float)
        if position.shape != (3,) or not np.all(np.isfinite(position)):
            raise ValueError("palm target position must be 3 finite numbers")
        if rotation is not None:
            rotation = np.asarray(rotation, float)
            if rotation.shape != (3, 3) or not np.all(np.isfinite(rotation)):
                raise ValueError("palm target rotation must be a finite 3x3 matrix")
        if self.phase != "manual":
            self.set_manual()
        self.target = position
        if rotation is not None:
            self.target_rotation = rotation

    def _enter(self, phase: str) -> None:
        self.phase = phase
        self.phase_time = 0.0

    # --- behaviour --------------------------------------------------------------------------
    @property
    def holding_by_contact(self) -> bool:
        """True once the grasp is fully let go."""
        return self.grasp_weight <= 0.0

    def step(
        self,
        dt: float,
        palm_force: float,
        palm_load: float,
        plate_force: float,
        band: tuple[float, float] | None,
        box_rotation: np.ndarray,
    ) -> None:
        """Advance dt (s). palm_force, palm_load: normal and tangential force (N) felt in the palm;
        plate_force: the robot's normal force (N); band: (f_n_min, f_n_max) of the running
        lifting, None when stopped; box_rotation: the box's orientation (it is kept level)."""
        low, high = band if band is not None else (0.0, 0.0)
        human_step(
            self.state,
            self.constants,
            dt,
            palm_force,
            palm_load,
            plate_force,
            band is not None,
            low,
            high,
            np.asarray(box_rotation, float),
        )

    def tremor(self, t: float) -> np.ndarray:
        """Physiological tremor (m) in the palm plane (`tremor` below)."""
        return tremor(self.state, t)

    def tilted_level(self) -> np.ndarray:
        """The box orientation the wrist aims at (`tilted_level` below)."""
        return tilted_level(self.state, self.constants)

    def hand_wrench(self, box: BoxPose, palm_force: float) -> tuple[np.ndarray, np.ndarray]:
        """Force (N) and moment about the box centre (Nm), world, that the hand applies besides the
        palm contact (`hand_wrench` below)."""
        force, moment = np.zeros(3), np.zeros(3)
        hand_wrench(
            self.state,
            self.constants,
            box.position,
            box.rotation,
            box.velocity,
            box.angular_velocity,
            palm_force,
            force,
            moment,
        )
        return force, moment


@njit(cache=True)
def _enter(s, phase):
    s[PHASE] = phase
    s[PHASE_TIME] = 0.0


@njit(cache=True)
def human_step(s, k, dt, palm_force, palm_load, plate_force, band_on, band_low, band_high, box_rotation):
    """Advance the person's state `s` by dt (s) (VirtualHuman.step's arguments; `k` its constants):
    the scripted trial (docs/design.md, "The experiment") or the manual target follower; in both,
    the person lets go of the grasp once the robot's grip, as felt, stays in the band; then the
    squeeze regulation (module docstring) and the palm's pose with tremor."""
    s[TIME] += dt
    s[PHASE_TIME] += dt
    if s[LETTING_GO] == 0.0:
        # felt grip: first-order low-pass with the feel time constant
        s[FELT_GRIP] += dt / (k[FEEL_TIME_CONSTANT] + dt) * (plate_force - s[FELT_GRIP])
        felt = s[FELT_GRIP]
        in_band = band_on and band_low > 0.0 and band_low <= felt <= band_high
        s[GRIP_TIME] = s[GRIP_TIME] + dt if in_band else 0.0
        if s[GRIP_TIME] >= k[GRIP_DWELL]:  # release(): let go over release_time
            s[LETTING_GO] = 1.0
            if s[PHASE] == GRASPING:
                _enter(s, RELEASING)
    phase = s[PHASE]
    if phase == RELEASING and s[GRASP_WEIGHT] <= 0.0:
        _enter(s, SETTLING)
    elif phase == SETTLING and s[PHASE_TIME] >= k[SETTLE_TIME]:
        _enter(s, CARRYING)
    elif phase == CARRYING:
        offset = path_offset(s[MOVES : MOVES + 9].reshape((3, 3)), s[DURATIONS : DURATIONS + 3], s[PHASE_TIME])
        for i in range(3):
            s[HAND + i] = s[START + i] + offset[i]
        if s[PHASE_TIME] >= s[PATH_DURATION] - s[HOLD]:
            _enter(s, HOLDING)
    elif phase == HOLDING and s[PHASE_TIME] >= s[HOLD]:
        _enter(s, DONE)
    elif phase == MANUAL:
        _follow_target(s, k, dt)
    rotation = s[ROTATION : ROTATION + 9].reshape((3, 3))
    if s[LETTING_GO] != 0.0:
        if s[HAS_LEVEL] == 0.0:
            s[BOX_LEVEL : BOX_LEVEL + 9] = box_rotation.ravel()
            s[HAS_LEVEL] = 1.0
        s[GRASP_WEIGHT] = max(0.0, s[GRASP_WEIGHT] - dt / k[RELEASE_TIME])
    if s[GRASP_WEIGHT] < 1.0:  # the palm regulates its push once the grasp is loosened
        # grip-load coupling (Johansson & Westling 1984): squeeze at least grip_load_ratio x load
        squeeze_target = max(s[SQUEEZE_FORCE], k[GRIP_LOAD_RATIO] * palm_load)
        ds = k[K_F] * (squeeze_target - palm_force) - k[K_P] * s[SQUEEZE]
        s[SQUEEZE] += min(max(ds, -k[V_SQUEEZE_MAX]), k[V_SQUEEZE_MAX]) * dt
    shake = tremor(s, s[TIME])
    for i in range(3):
        new = s[HAND + i] + s[SQUEEZE] * rotation[i, 2] + shake[i]
        s[VELOCITY + i] = (new - s[POSITION + i]) / dt
        s[POSITION + i] = new


@njit(cache=True)
def _follow_target(s, k, dt):
    """Manual mode: hand' = k (target - hand), |hand'| <= manual_speed; same for the rotation."""
    step = np.empty(3)
    for i in range(3):
        step[i] = k[MANUAL_GAIN] * dt * (s[TARGET + i] - s[HAND + i])
    norm = math.sqrt(step[0] * step[0] + step[1] * step[1] + step[2] * step[2])
    limit = k[MANUAL_SPEED] * dt
    scale = limit / norm if norm > limit else 1.0
    for i in range(3):
        s[HAND + i] += step[i] * scale
    rotation = s[ROTATION : ROTATION + 9].reshape((3, 3))
    target = s[TARGET_ROTATION : TARGET_ROTATION + 9].reshape((3, 3))
    w = np.minimum(np.maximum(k[MANUAL_GAIN] * log3(target @ rotation.T), -1.0), 1.0)
    rotation[:, :] = exp3(w * dt) @ rotation
    s[ANGULAR_VELOCITY : ANGULAR_VELOCITY + 3] = w


@njit(cache=True)
def tremor(s, t):
    """Physiological tremor (m) in the palm plane: A sin(2 pi f_i t + phi_i) along palm x, y
    (along the normal the person regulates force, so no position tremor there)."""
    a = s[TREMOR_AMPLITUDE]
    x = a * math.sin(2.0 * math.pi * s[TREMOR_FREQUENCY] * t + s[TREMOR_PHASE])
    y = a * math.sin(2.0 * math.pi * s[TREMOR_FREQUENCY + 1] * t + s[TREMOR_PHASE + 1])
    rotation = s[ROTATION : ROTATION + 9].reshape((3, 3))
    return rotation[:, 0] * x + rotation[:, 1] * y


@njit(cache=True)
def tilted_level(s, k):
    """The box orientation the wrist aims at: as let go, tilted by the participant's tilt about the
    carry direction along the carry (minimum-jerk over the path's duration)."""
    level = s[BOX_LEVEL : BOX_LEVEL + 9].reshape((3, 3)).copy()
    phase, tilt = s[PHASE], s[TILT]
    if tilt == 0.0 or phase not in (CARRYING, HOLDING, DONE):
        return level
    progress = 1.0 if phase != CARRYING else minimum_jerk(s[PHASE_TIME] / (s[PATH_DURATION] - s[HOLD]))
    return exp3(k[CARRY_AXIS : CARRY_AXIS + 3] * (tilt * progress)) @ level


@njit(cache=True)
def hand_wrench(s, k, box_position, box_rotation, box_velocity, box_omega, palm_force, force, moment):
    """Force (N) and moment about the box centre (Nm), world, into `force` and `moment`, that the
    hand applies besides the palm contact: the grasp (a 6-D spring-damper to where the box was
    grasped, faded out by the grasp weight) and, once let go, the wrist's moment that keeps the box level:
        m_w = K_w log(R_level R_box^T) - D_w w_box,   |m_w| <= hand_lever * F_palm
    (a hand can only turn the box while it presses on it)."""
    force[:] = 0.0
    moment[:] = 0.0
    weight = s[GRASP_WEIGHT]
    rotation = s[ROTATION : ROTATION + 9].reshape((3, 3))
    omega = s[ANGULAR_VELOCITY : ANGULAR_VELOCITY + 3]
    if s[HAS_GRASP] != 0.0 and weight > 0.0:
        arm = rotation @ s[GRASP_POSITION : GRASP_POSITION + 3]
        target_velocity = s[VELOCITY : VELOCITY + 3] + np.cross(omega, arm)
        for i in range(3):
            target = s[POSITION + i] + arm[i]
            force[i] = weight * (
                k[GRASP_STIFFNESS] * (target - box_position[i])
                + k[GRASP_DAMPING] * (target_velocity[i] - box_velocity[i])
            )
        rot_err = log3((rotation @ s[GRASP_ROTATION : GRASP_ROTATION + 9].reshape((3, 3))) @ box_rotation.T)
        for i in range(3):
            moment[i] = weight * (
                k[GRASP_ROT_STIFFNESS] * rot_err[i] + k[GRASP_ROT_DAMPING] * (omega[i] - box_omega[i])
            )
    if s[HAS_LEVEL] != 0.0:
        wrist = k[WRIST_STIFFNESS] * log3(tilted_level(s, k) @ box_rotation.T) - k[WRIST_DAMPING] * box_omega
        capacity = k[HAND_LEVER] * max(palm_force, 0.0)
        norm = math.sqrt(wrist[0] * wrist[0] + wrist[1] * wrist[1] + wrist[2] * wrist[2])
        if norm > capacity:
            wrist = wrist * (capacity / norm)
        for i in range(3):
            moment[i] += (1.0 - weight) * wrist[i]
