"""The simulated lab: robot + plate, box, virtual human, sensor and controller, stepped at 1 kHz.

One `step()` is one control period dt (default 1 ms):
  1. sense:   F_ext = sensor(plate contact wrench at the EE, EE frame)
  2. control: twist_base = controller.step(F_ext, T_ee_to_base, params, dt)   (or move_to_start)
  3. robot:   Cartesian velocity interface (DLS IK, limits, reflexes) integrates q
  4. human:   the palm moves (path / target, squeeze regulation, tremor, grasp)
  5. physics: plate and palm contacts -> forces on the box -> box integration (substeps)
The robot is kinematic: contact forces do not push it; it follows only the controller's command.
"""

from __future__ import annotations

import traceback
from dataclasses import dataclass, field, replace

import numpy as np

from sim import compiled_step
from sim.controllers.external import COMMAND_PERIOD
from sim.controllers.interface import Controller, ControllerFault, LiftingParams, lifting_vector
from sim.controllers.lifting_law import LiftingLawController
from sim.controllers.sp import SPController
from sim.monitor import NONE, TrialMonitor, TrialOutcome
from sim.person.human import HumanParams, PickAndPlace, VirtualHuman
from sim.person.participants import PARTICIPANTS, Participant
from sim.physics.box import GRAVITY, Box, BoxParams
from sim.physics.contact import ContactParams, ContactResult, PatchContact, PatchGeometry, result_of
from sim.physics.sensor import SensorParams, WrenchSensor, wrench_at_ee
from sim.robot.cartesian_velocity import OK, CartesianVelocityInterface, Reflex
from sim.robot.joint_trajectory import BrakeThenMove, JointBrake, JointTrajectory
from sim.robot.panda import SIDE_Q, PandaModel
from sim.robot.plate import Plate
from sim.robot.teleop import Jog

_PATCHABLE_HUMAN = {"step", "hand_wrench"}  # VirtualHuman's methods the compiled rest runs as kernels


@dataclass(frozen=True)
class WorldConfig:
    """Everything that defines a fresh world (SI units)."""

    dt: float = 0.001  # s, control period (1 kHz)
    physics_substeps: int = 1
    plate: Plate = Plate()
    plate_grid: tuple[int, int] = (6, 6)
    plate_contact: ContactParams = ContactParams(mu=0.6)
    palm_size: tuple[float, float] = (0.08, 0.08)  # m
    palm_grid: tuple[int, int] = (5, 5)
    palm_contact: ContactParams = ContactParams(normal_stiffness=1.0e4, normal_damping=80.0, mu=1.3)
    box: BoxParams = BoxParams()
    sensor: SensorParams = SensorParams()
    human: HumanParams = HumanParams()
    path: PickAndPlace = PickAndPlace()
    participant: str = "calm"
    start_gap: float = 0.03  # m between plate and box at the start
    start_q: tuple[float, ...] = tuple(SIDE_Q)
    seed: int = 0
    command_period: float = COMMAND_PERIOD  # s, a node's velocity command must be renewed within this


def stable_substeps(config: WorldConfig) -> int:
    """Physics substeps that keep the box's explicit integration stable (at least
    config.physics_substeps). Explicit Euler of m v' = -c v is stable for c dt/m < 2; we keep
    c dt_sub / m <= 1.5 for the dampings that can act on the box at once:
        c_lin = plate and palm (normal + tangential) + grasp          (N s/m, on m in kg)
        c_rot = c_lin_tangential (0.1 m lever) + grasp + wrist           (Nm s/rad, on I_min in kg m^2)
    (a 1 kg box needs 1 substep; a 0.05 kg box, 8)."""
    plate, palm, human, box = config.plate_contact, config.palm_contact, config.human, config.box
    c_tangential = plate.tangential_damping + palm.tangential_damping
    c_lin = plate.normal_damping + palm.normal_damping + c_tangential + human.grasp_damping
    lever = max(box.size) / 2.0  # m, a face's contact to the box centre
    c_rot = c_tangential * lever**2 + human.grasp_rot_damping + human.wrist_damping
    rate = config.dt * max(c_lin / box.mass, c_rot / float(np.min(np.diag(box.inertia_body))))
    return max(config.physics_substeps, int(np.ceil(rate / 1.5)))


@dataclass
class Snapshot:
    """A consistent copy of the world's state (what the server publishes)."""

    time: float
    q: np.ndarray
    qdot: np.ndarray
    transform_ee_to_base: np.ndarray
    wrench_ee: np.ndarray  # F_ext as measured (noise, filter)
    wrench_ee_true: np.ndarray  # noise-free
    twist_command: np.ndarray  # base frame
    box_position: np.ndarray
    box_rotation: np.ndarray
    palm_position: np.ndarray
    palm_rotation: np.ndarray
    plate: ContactResult
    palm: ContactResult
    lifting: LiftingParams
    error: str | None
    human_phase: str
    moving_to_start: bool
    trial: TrialOutcome  # the scripted participant's trial: running, or its result


@dataclass
class World:
    config: WorldConfig = field(default_factory=WorldConfig)
    controller: Controller = field(default_factory=SPController)
    params: LiftingParams = field(default_factory=LiftingParams)

    def __post_init__(self) -> None:
        cfg = self.config
        self.model = PandaModel()
        self.arm = CartesianVelocityInterface(self.model, np.array(cfg.start_q))
        chain = self.arm.chain  # world_step's robot: the limits and the kinematic chain (fixed for a world)
        self._robot = (
            self.arm.constants(),
            chain.rotations,
            chain.translations,
            chain.axes,
            chain.flange_rotation,
            chain.flange_translation,
        )
        self.plate_contact = PatchContact(
            PatchGeometry(cfg.plate.width, cfg.plate.height, *cfg.plate_grid), cfg.plate_contact
        )
        self.palm_contact = PatchContact(PatchGeometry(*cfg.palm_size, *cfg.palm_grid), cfg.palm_contact)
        self.params.plate_offset = cfg.plate.offset
        self.substeps = stable_substeps(cfg)  # physics substeps per step (recomputed when the box or contact changes)
        self.participant: Participant | None = None  # overrides config.participant when set
        self.trial = TrialMonitor()
        # the step's own arrays, changed in place by the compiled step (sim/compiled_step.py)
        self.wrench_ee_true = np.zeros(6)  # F_ext without noise (N, Nm; EE frame)
        self.wrench_ee = np.zeros(6)  # F_ext as measured
        self.twist_command = np.zeros(6)  # the controller's last command (base frame)
        self.plate_out = np.zeros(20)  # what the plate's contact did in the last step (contact._patch_kernel's layout)
        self.palm_out = np.zeros(20)  # the same for the palm
        self._lifting: tuple = ((), np.zeros(0))  # (the params' values, their lifting_vector)
        # world_step's sensor noise and built-in law when it does not sense and control: unread
        # placeholders of the types a step that does passes (one compiled specialization)
        self._no_noise = np.zeros(6)
        self._no_law = (-1, np.zeros(1), np.zeros(1), np.zeros(1))
        self.reset()

    # --- set-up -----------------------------------------------------------------------------
    def reset(self, participant: Participant | None = None, seed: int | None = None) -> None:
        """Robot at the start pose, box held by the person a few cm in front of the plate."""
        cfg = self.config
        self.rng = np.random.default_rng(cfg.seed if seed is None else seed)
        self.time = 0.0
        self.motion: JointTrajectory | BrakeThenMove | JointBrake | None = None
        self.jog: Jog | None = None
        self.arm.reset(np.array(cfg.start_q))
        self.controller.reset()
        self.sensor = WrenchSensor(cfg.sensor, self.rng)
        self.plate_contact.reset()
        self.palm_contact.reset()
        transform = self.arm.transform_ee_to_base
        normal = transform[:3, 2]
        plate_centre = transform[:3, 3] + normal * cfg.plate.offset
        half = np.asarray(cfg.box.size) / 2.0
        # the box's -y face looks at the plate (the side pose's normal is base +y)
        box_centre = plate_centre + normal * (cfg.start_gap + half[1])
        self.box = Box(cfg.box, box_centre)
        palm_rotation = np.column_stack((transform[:3, 0], -transform[:3, 1], -normal))  # z pushes toward the robot
        if participant is not None:
            self.participant = participant
        self.human = VirtualHuman(
            box_centre + normal * half[1],
            palm_rotation,
            self.participant or PARTICIPANTS[cfg.participant],
            cfg.path,
            cfg.human,
            self.rng,
        )
        self.human.grasp(self.box.pose())
        for array in (self.wrench_ee_true, self.wrench_ee, self.twist_command, self.plate_out, self.palm_out):
            array[:] = 0.0  # the contacts at rest
        self.trial = TrialMonitor(self.trial.rules)  # no trial until lifting starts

    @property
    def plate_state(self) -> ContactResult:
        """What the plate's contact did to the box in the last step."""
        return result_of(self.plate_out)

    @property
    def palm_state(self) -> ContactResult:
        """What the palm's contact did to the box in the last step."""
        return result_of(self.palm_out)

    # --- commands (what the lab's services do) -----------------------------------------------
    def start_lifting(self, force: float) -> str:
        """The start service: the controller's handler (the lab's semantics for the built-ins)."""
        return self.controller.start(self.params, force)

    def stop_lifting(self) -> str:
        """The stop service: the controller's handler."""
        return self.controller.stop(self.params)

    def move_to_start(self, peak_velocity: float = 0.5) -> JointTrajectory | BrakeThenMove:
        """Drive the robot to the start pose with a smooth joint motion (controller paused; a teleop
        jog is cancelled). Joints still moving are braked to rest first."""
        self.jog = None
        goal = np.array(self.config.start_q)
        if np.any(self.arm.qdot):
            self.motion = BrakeThenMove(self.arm.qdot, self.arm.q, goal, peak_velocity, self.arm.qdd_max)
        else:
            self.motion = JointTrajectory(self.arm.q, goal, peak_velocity, self.arm.qdd_max)
        return self.motion

    def set_sensor(self, **changes) -> None:
        """Change sensor parameters (SensorParams fields) now and for later resets."""
        self.config = replace(self.config, sensor=replace(self.config.sensor, **changes))
        self.sensor.params = self.config.sensor

    def set_box(self, **changes) -> None:
        """Change the box (BoxParams fields) now and for later resets."""
        self.config = replace(self.config, box=replace(self.config.box, **changes))
        self.box.set_params(self.config.box)
        self.substeps = stable_substeps(self.config)

    def set_plate_contact(self, **changes) -> None:
        """Change the plate's contact material (ContactParams fields) now and for later resets."""
        self.config = replace(self.config, plate_contact=replace(self.config.plate_contact, **changes))
        self.plate_contact.set_params(self.config.plate_contact)
        self.substeps = stable_substeps(self.config)

    def set_controller(self, controller: Controller) -> None:
        """Swap the controller, bumpless: one that can (`continue_from`, the built-ins) starts from
        the running command, so a switch while lifting never jumps the command (no reflex); any
        other starts from rest."""
        controller.reset()
        continue_from = getattr(controller, "continue_from", None)
        if continue_from is not None and not self.error:
            continue_from(self.twist_command.copy())
        self.controller = controller

    def set_participant(self, participant: Participant) -> None:
        """The person the virtual human plays, now and for later resets."""
        self.participant = participant
        self.human.set_participant(participant)

    def stop_motion(self) -> None:
        """Cancel move_to_start: the joints brake to rest."""
        if self.motion is not None and not isinstance(self.motion, JointBrake):
            self.motion = JointBrake(self.arm.qdot)

    def start_jog(self, twist_base: np.ndarray, duration: float = 0.5) -> None:
        """Teleop: move the EE with `twist_base` for `duration` s (only while lifting is stopped)."""
        if self.params.running:
            raise RuntimeError("teleop is disabled while cooperative lifting runs")
        self.jog = Jog(twist_base, duration).start_from(self.twist_command)

    def fail(self, reason: str) -> None:
        """Stop the robot with an error (like a reflex): zero command until recover()."""
        self.arm.stop_with_error(reason)

    def recover(self) -> None:
        """Clear the reflex error (error_recovery); the controller restarts from rest."""
        self.arm.recover()
        self.controller.reset()

    @property
    def error(self) -> str | None:
        return self.arm.error

    @property
    def commanded(self) -> bool:
        """Somebody commands the robot: lifting runs, a motion or teleop is under way, or the last
        command was not zero (a real-time server keeps 1 ms granularity then: app/runtime/loop.py)."""
        return (
            self.params.running or self.motion is not None or self.jog is not None or bool(np.any(self.twist_command))
        )

    # --- stepping ---------------------------------------------------------------------------
    def step(self) -> None:
        """One control period: one compiled call with a built-in controller (sim/compiled_step.py);
        with any other controller, compiled sense, the controller in Python, one compiled call for
        the robot and the rest; with a joint motion or a jog, the robot in Python."""
        dt = self.config.dt
        human, params, trial = self.human, self.params, self.trial
        if trial.state == "none" and params.running and human.phase == "grasping":
            trial.begin(self.time, human.participant.name, self)  # lifting started: a trial
        controller = self.controller
        law = controller.law() if isinstance(controller, LiftingLawController) else None
        jogging = self.jog is not None and not params.running
        rest_compiled = self._components_plain()
        kind = OK
        if self.motion is None and not jogging and rest_compiled:
            self.jog = None
            if law is not None and isinstance(controller, LiftingLawController):  # a built-in: one compiled call
                law_arguments = (law, controller.state, self._lifting_vector(), controller.constants())
                kind, j, value, self.box._steps, event = compiled_step.world_step(
                    *self._step_arguments(compiled_step.SENSE_CONTROL, dt, self.sensor.next_noise(), law_arguments)
                )
            else:  # compiled sense, the controller in Python, the compiled robot and rest
                self._sense(dt)
                self.twist_command[:] = self._control(self.arm.transform_ee_to_base, dt)
                kind, j, value, self.box._steps, event = compiled_step.world_step(
                    *self._step_arguments(compiled_step.ROBOT, dt)
                )
        else:  # a joint motion, a jog, or patched components: the robot (and the rest) in Python
            self._sense(dt)
            self._control_and_move(dt)
            if rest_compiled:
                _, _, _, self.box._steps, event = compiled_step.world_step(
                    *self._step_arguments(compiled_step.REST, dt)
                )
            else:
                self._rest_in_python(dt)
                event = None
        if kind != OK:  # the compiled robot halted on a limit: its reflex's reason
            self.arm.stop_with_error(self.arm.reflex_reason(kind, j, value))
        self.time += dt
        if event is None:
            trial.update(self)  # the trial's success rule (sim/monitor.py)
        elif event != NONE:
            trial.conclude(event, self)

    def _sense(self, dt: float) -> None:
        """1. sense, compiled: F_ext from the true wrench."""
        sensor = self.sensor
        compiled_step.world_sense(
            sensor.state, sensor.next_noise(), sensor.scales(), dt, self.wrench_ee_true, self.wrench_ee
        )

    def _components_plain(self) -> bool:
        """True when the human, the box and the contacts are the lab's own, unpatched (the compiled
        rest runs their kernels); a replaced or patched one (a subclass, a method set on the
        instance, e.g. a fault injected by a test) runs through its Python methods."""
        human, box = self.human, self.box
        return (
            type(human) is VirtualHuman
            and not _PATCHABLE_HUMAN & vars(human).keys()
            and type(box) is Box
            and "step" not in vars(box)
            and type(self.plate_contact) is PatchContact
            and "step_into" not in vars(self.plate_contact)
            and type(self.palm_contact) is PatchContact
            and "step_into" not in vars(self.palm_contact)
        )

    def _rest_in_python(self, dt: float) -> None:
        """4. human and 5. physics through the components' Python methods (the same kernels, one call each)."""
        params, palm = self.params, self.palm_out
        band = (params.f_n_min, params.f_n_max) if params.running else None
        self.human.step(
            dt, float(palm[9]), float(np.linalg.norm(palm[10:13])), float(self.plate_out[9]), band, self.box.rotation
        )
        sub_dt = dt / self.substeps
        for _ in range(self.substeps):
            self._physics(sub_dt)

    def _physics(self, dt: float) -> None:
        arm = self.arm
        transform = arm.transform_ee_to_base
        rotation = np.ascontiguousarray(transform[:3, :3])
        arm_plate = rotation[:, 2] * self.config.plate.offset
        position_plate = transform[:3, 3] + arm_plate
        twist = arm.twist_base
        velocity_plate = twist[:3] + np.cross(twist[3:], arm_plate)
        box = self.box.pose()
        self.plate_contact.step_into(
            rotation, position_plate, velocity_plate, twist[3:].copy(), box, dt, self.plate_out
        )
        human = self.human
        self.palm_contact.step_into(
            human.rotation, human.position, human.velocity, human.angular_velocity, box, dt, self.palm_out
        )
        plate, palm = self.plate_out, self.palm_out
        grasp_force, grasp_moment = human.hand_wrench(box, float(palm[9]))
        self.box.step(plate[0:3] + palm[0:3] + grasp_force, plate[3:6] + palm[3:6] + grasp_moment, dt)
        self.wrench_ee_true[:] = wrench_at_ee(plate[0:3], plate[6:9], position_plate, transform)

    def _lifting_vector(self) -> np.ndarray:
        """lifting_vector(self.params), rebuilt only when a parameter changed."""
        key = tuple(vars(self.params).values())
        if key != self._lifting[0]:
            self._lifting = (key, lifting_vector(self.params))
        return self._lifting[1]

    def _step_arguments(self, mode: int, dt: float, noise: np.ndarray | None = None, law: tuple | None = None) -> tuple:
        """world_step's arguments in its signature's order (sim/compiled_step.py lists them): `mode`,
        the sensor with this step's `noise`, the built-in `law` (both read in SENSE_CONTROL only:
        placeholders of the same types otherwise), the robot, then the rest after this step."""
        params, box, human, plate, palm = self.params, self.box, self.human, self.plate_contact, self.palm_contact
        sensor, trial = self.sensor, self.trial
        return (
            mode,
            sensor.state,
            self._no_noise if noise is None else noise,
            sensor.scales(),
            self.wrench_ee,
            *(self._no_law if law is None else law),
            *self._robot,
            self.arm.state,
            self.twist_command,
            float(dt),
            int(self.substeps),
            float(self.config.plate.offset),
            bool(params.running),
            float(params.f_n_min),
            float(params.f_n_max),
            human.state,
            human.constants,
            box.position,
            box.rotation,
            box.velocity,
            box.angular_velocity,
            box.half_size,
            float(box.params.mass),
            box._inertia,
            box._inertia_inv,
            GRAVITY,
            box._steps,
            plate.points_patch,
            plate.bristles,
            plate.constants,
            palm.points_patch,
            palm.bristles,
            palm.constants,
            self.plate_out,
            self.palm_out,
            self.wrench_ee_true,
            trial.state_array,
            trial.rules_vector,
            self.time + dt,
            float(params.mu),
        )

    def _control_and_move(self, dt: float) -> None:
        """2-3. control and robot, in Python: a joint motion, a jog, or a controller's twist."""
        transform = self.arm.transform_ee_to_base
        if self.motion is not None:
            self.arm.command_joint_velocity(self.motion.command(self.arm.q, dt), dt)
            self.twist_command[:] = self.arm.twist_base
            if self.motion.done or self.arm.error:
                self.motion = None
        elif self.jog is not None and not self.params.running:
            self.twist_command[:] = self.jog.step(dt)
            self.arm.command_twist(self.twist_command, dt)
            if self.jog.done or self.arm.error:
                self.jog = None
        else:
            self.jog = None
            self.twist_command[:] = self._control(transform, dt)
            self.arm.command_twist(self.twist_command, dt)

    def run(self, duration: float) -> None:
        """Step for `duration` seconds of simulated time."""
        for _ in range(int(round(duration / self.config.dt))):
            self.step()

    def _control(self, transform: np.ndarray, dt: float) -> np.ndarray:
        """The controller's twist; an exception is an error state, never a crash of the loop."""
        try:
            twist = np.asarray(
                self.controller.step(self.wrench_ee.copy(), transform.copy(), self.params, dt), dtype=float
            )
        except ControllerFault as fault:
            self.fail(f"controller error: {fault}")
            return np.zeros(6)
        except Reflex as reflex:  # a reflex the controller reports (e.g. an external command went stale)
            self.arm.error = str(reflex)
            return np.zeros(6)
        except Exception as exc:  # noqa: BLE001 - any controller failure stops the robot
            self.fail("controller error: " + "".join(traceback.format_exception_only(exc)).strip())
            return np.zeros(6)
        if twist.shape != (6,):
            self.fail(f"controller error: twist must have shape (6,), got {twist.shape}")
            return np.zeros(6)
        return twist

    # --- reading ----------------------------------------------------------------------------
    def snapshot(self) -> Snapshot:
        arm, human = self.arm, self.human
        return Snapshot(
            time=self.time,
            q=arm.q.copy(),
            qdot=arm.qdot.copy(),
            transform_ee_to_base=arm.transform_ee_to_base.copy(),
            wrench_ee=self.wrench_ee.copy(),
            wrench_ee_true=self.wrench_ee_true.copy(),
            twist_command=self.twist_command.copy(),
            box_position=self.box.position.copy(),
            box_rotation=self.box.rotation.copy(),
            palm_position=human.position.copy(),
            palm_rotation=human.rotation.copy(),
            plate=self.plate_state,
            palm=self.palm_state,
            lifting=LiftingParams(**vars(self.params)),
            error=arm.error,
            human_phase=human.phase,
            moving_to_start=self.motion is not None,
            trial=self.trial.outcome(),
        )
