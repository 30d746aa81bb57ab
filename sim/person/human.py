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
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sim.person.participants import PARTICIPANTS, Participant
from sim.physics.contact import BoxPose
from sim.signals import LowPass, minimum_jerk
from sim.spatial import cross3, norm3, rotation_exp, rotation_log


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

    def offset(self, t: float) -> np.ndarray:
        """Hand displacement (m) from the start at time t (s) since the carry began."""
        offset = np.zeros(3)
        for move, duration in self.segments:
            if t <= 0.0:
                break
            offset = offset + move * minimum_jerk(t / duration)
            t -= duration
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


class VirtualHuman:
    """Scripted (a participant following a pick-and-place path) or manual (target set directly)."""

    PHASES = ("grasping", "releasing", "settling", "carrying", "holding", "done", "manual")

    def __init__(
        self,
        position: np.ndarray,
        rotation: np.ndarray,
        participant: Participant = PARTICIPANTS["calm"],
        path: PickAndPlace = PickAndPlace(),
        params: HumanParams = HumanParams(),
        rng: np.random.Generator | None = None,
    ) -> None:
        self.params = params
        self.path_spec = path
        self.rotation = np.array(rotation, float)  # palm -> world; its z is the push direction
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

    def reset(self) -> None:
        self.time = 0.0  # s since reset
        self.hand = self.start.copy()  # hand position without squeeze and tremor (m)
        self.target = self.start.copy()  # where the hand is heading (manual mode)
        self.target_rotation = self.rotation.copy()
        self.position = self.start.copy()  # palm centre (m)
        self.velocity = np.zeros(3)
        self.angular_velocity = np.zeros(3)
        self.squeeze = 0.0  # s (m)
        self.phase = "grasping"
        self.phase_time = 0.0
        self.grip_time = 0.0  # s the robot's grip has been in the band
        self.felt_grip = LowPass(0.0)  # N, the robot's push as the person feels it
        self.letting_go = False
        self.box_level: np.ndarray | None = None  # box orientation the person keeps once let go
        self.grasp_weight = 1.0
        self.grasp_offset: tuple[np.ndarray, np.ndarray] | None = None  # box pose in the palm frame

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
        self.target = self.hand.copy()
        self.target_rotation = self.rotation.copy()
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
        self.target = position.copy()
        if rotation is not None:
            self.target_rotation = rotation.copy()

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
        self.time += dt
        self.phase_time += dt
        self._behave(dt, plate_force, band)
        p = self.params
        if self.letting_go:
            if self.box_level is None:
                self.box_level = box_rotation.copy()
            self.grasp_weight = max(0.0, self.grasp_weight - dt / p.release_time)
        if self.grasp_weight < 1.0:  # the palm regulates its push once the grasp is loosened
            # grip-load coupling (Johansson & Westling 1984): squeeze at least grip_load_ratio x load
            squeeze_target = max(self.participant.squeeze_force, p.grip_load_ratio * palm_load)
            ds = p.k_f * (squeeze_target - palm_force) - p.k_p * self.squeeze
            self.squeeze += min(max(ds, -p.v_squeeze_max), p.v_squeeze_max) * dt
        new = self.hand + self.squeeze * self.rotation[:, 2] + self.tremor(self.time)
        self.velocity = (new - self.position) / dt
        self.position = new

    def _behave(self, dt: float, plate_force: float, band: tuple[float, float] | None) -> None:
        """The scripted trial (docs/design.md, "The experiment") or the manual target follower. In both, the
        person lets go of the grasp once the robot's grip, as felt, stays in the band."""
        p = self.params
        if not self.letting_go:
            felt = self.felt_grip.update(plate_force, dt, p.feel_time_constant)
            in_band = band is not None and band[0] > 0.0 and band[0] <= felt <= band[1]
            self.grip_time = self.grip_time + dt if in_band else 0.0
            if self.grip_time >= p.grip_dwell:
                self.release()
        phase = self.phase
        if phase == "releasing" and self.grasp_weight <= 0.0:
            self._enter("settling")
        elif phase == "settling" and self.phase_time >= p.settle_time:
            self._enter("carrying")
        elif phase == "carrying":
            self.hand = self.start + self.path.offset(self.phase_time)
            if self.phase_time >= self.path.duration - self.path.hold:
                self._enter("holding")
        elif phase == "holding" and self.phase_time >= self.path.hold:
            self._enter("done")
        elif phase == "manual":
            self._follow_target(dt)

    def _follow_target(self, dt: float) -> None:
        """Manual mode: hand' = k (target - hand), |hand'| <= manual_speed; same for the rotation."""
        p = self.params
        step = p.manual_gain * dt * (self.target - self.hand)
        norm = float(np.linalg.norm(step))
        limit = p.manual_speed * dt
        self.hand = self.hand + (step * (limit / norm) if norm > limit else step)
        w = np.clip(p.manual_gain * rotation_log(self.target_rotation @ self.rotation.T), -1.0, 1.0)
        self.rotation = rotation_exp(w * dt) @ self.rotation
        self.angular_velocity = w

    def _enter(self, phase: str) -> None:
        self.phase = phase
        self.phase_time = 0.0

    def tremor(self, t: float) -> np.ndarray:
        """Physiological tremor (m) in the palm plane: A sin(2 pi f_i t + phi_i) along palm x, y
        (along the normal the person regulates force, so no position tremor there)."""
        a = self.participant.tremor_amplitude
        fx, fy = self.tremor_freq
        px, py = self.tremor_phase
        x, y = a * math.sin(2.0 * math.pi * fx * t + px), a * math.sin(2.0 * math.pi * fy * t + py)
        return self.rotation[:, 0] * x + self.rotation[:, 1] * y

    def tilted_level(self) -> np.ndarray:
        """The box orientation the wrist aims at: as let go, tilted by participant.tilt about the
        carry direction along the carry (minimum-jerk over the path's duration)."""
        tilt = self.participant.tilt
        assert self.box_level is not None  # called once the box is let go (the wrist's moment)
        if tilt == 0.0 or self.phase not in ("carrying", "holding", "done"):
            return self.box_level
        progress = 1.0 if self.phase != "carrying" else minimum_jerk(self.phase_time / (self.path.duration - self.path.hold))
        axis = np.asarray(self.path_spec.carry_direction, float)
        return rotation_exp(axis / np.linalg.norm(axis) * tilt * progress) @ self.box_level

    def hand_wrench(self, box: BoxPose, palm_force: float) -> tuple[np.ndarray, np.ndarray]:
        """Force (N) and moment about the box centre (Nm), world, that the hand applies besides the
        palm contact: the grasp (a 6-D spring-damper to where the box was grasped, faded out by
        the grasp weight) and, once let go, the wrist's moment that keeps the box level:
            m_w = K_w log(R_level R_box^T) - D_w w_box,   |m_w| <= hand_lever * F_palm
        (a hand can only turn the box while it presses on it)."""
        force, moment = np.zeros(3), np.zeros(3)
        p = self.params
        if self.grasp_offset is not None and self.grasp_weight > 0.0:
            offset_palm, rotation_box_palm = self.grasp_offset
            arm = self.rotation @ offset_palm
            target = self.position + arm
            target_velocity = self.velocity + cross3(self.angular_velocity, arm)
            force = p.grasp_stiffness * (target - box.position) + p.grasp_damping * (target_velocity - box.velocity)
            rot_err = rotation_log((self.rotation @ rotation_box_palm) @ box.rotation.T)
            moment = p.grasp_rot_stiffness * rot_err + p.grasp_rot_damping * (self.angular_velocity - box.angular_velocity)
            force, moment = self.grasp_weight * force, self.grasp_weight * moment
        if self.box_level is not None:
            level = self.tilted_level()
            wrist = p.wrist_stiffness * rotation_log(level @ box.rotation.T) - p.wrist_damping * box.angular_velocity
            capacity = p.hand_lever * max(palm_force, 0.0)
            norm = norm3(wrist)
            if norm > capacity:
                wrist = wrist * (capacity / norm)
            moment = moment + (1.0 - self.grasp_weight) * wrist
        return force, moment
