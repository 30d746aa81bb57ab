"""The world's 1 kHz step as compiled code (numba): the components' kernels composed, so a step
is one call from Python (World.step, sim/world.py).

    world_step(SENSE_CONTROL) = sense (sensor.measure_into)
                              + control (compiled_law.lifting_law_step: SP or patch, steps 0-6)
                              + robot + rest
    world_step(ROBOT)         = robot (cartesian_velocity.arm_command_twist: limits, DLS, the compiled
                                Panda kinematics read out of pinocchio's model, sim/robot/panda_kinematics.py,
                                of a twist from Python: a plug-in's, a node's) + rest
    world_step(REST)          = rest: human (human.human_step) + physics (contact.patch_step x 2,
                                human.hand_wrench, box.box_step, sensor.wrench_at_ee_into; substeps)
                                + the trial's rule (monitor.monitor_update)
    world_sense               = sense alone, before a controller that runs in Python

Every piece is the function the component's own Python method runs (one source per fact), but
for the built-in controllers, whose Python classes are the law of record a student reads and a
sandboxed plug-in imports without numba (sim/controllers/compiled_law.py is tested equal to
them); the state is the components' arrays (sim/state.py), changed in place. With any other controller (a
student's plug-in, a node's external command) or a joint motion, World.step runs `world_sense`,
the controller in Python, then `world_step(ROBOT)`: compiled sense, Python control, compiled
robot and rest (a joint motion or a jog: the robot in Python, then `world_step(REST)`).

The arguments are listed once, in world_step's signature (World._step_arguments builds them in
that order), flat: numba types an array argument through a direct table, an array inside a
tuple through a slower fingerprint (measured: ~1 us a step for the ~35 arrays,
docs/performance.md). Inside, they travel in groups (the box, a patch, the human, the trial).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from sim.controllers.compiled_law import lifting_law_step
from sim.monitor import monitor_update
from sim.person import human as h
from sim.person.human import hand_wrench, human_step
from sim.physics.box import box_step
from sim.physics.contact import patch_step
from sim.physics.sensor import measure_into, wrench_at_ee_into
from sim.robot.cartesian_velocity import ERROR, OK, TRANSFORM, TWIST_BASE, arm_command_twist

REST, ROBOT, SENSE_CONTROL = 0, 1, 2  # world_step's modes: what runs before the rest


@njit(cache=True)
def world_sense(sensor_state, noise, scales, dt, wrench_ee_true, wrench_ee):
    """1. sense: F_ext = the sensor's sample of the true wrench (noise, low-pass) into wrench_ee."""
    measure_into(wrench_ee_true, noise, scales, dt, sensor_state, wrench_ee)


@njit(cache=True)
def _physics(dt, plate_offset, arm, human, box, plate, palm, plate_out, palm_out, wrench_ee_true, box_steps):
    """5. physics for dt: plate and palm contacts, the hand's wrench, the box; the true F_ext.
    The groups as _rest's; returns the box's steps."""
    human_state = human[0]  # (state, constants)
    box_position, box_rotation, box_velocity, box_omega, box_half, box_mass, box_inertia, box_inertia_inv, gravity = box
    box_pose = (box_position, box_rotation, box_velocity, box_omega, box_half)
    transform = arm[TRANSFORM : TRANSFORM + 16].reshape((4, 4))
    rotation = transform[:3, :3].copy()
    arm_plate = rotation[:, 2] * plate_offset
    position_plate = transform[:3, 3] + arm_plate
    twist = arm[TWIST_BASE : TWIST_BASE + 6]
    omega = twist[3:].copy()
    velocity_plate = twist[:3] + np.cross(omega, arm_plate)
    patch_step(*plate, rotation, position_plate, velocity_plate, omega, *box_pose, dt, plate_out)
    palm_rotation = human_state[h.ROTATION : h.ROTATION + 9].reshape((3, 3))
    patch_step(
        *palm,
        palm_rotation,
        human_state[h.POSITION : h.POSITION + 3],
        human_state[h.VELOCITY : h.VELOCITY + 3],
        human_state[h.ANGULAR_VELOCITY : h.ANGULAR_VELOCITY + 3],
        *box_pose,
        dt,
        palm_out,
    )
    grasp_force, grasp_moment = np.empty(3), np.empty(3)
    hand_wrench(*human, *box_pose[:4], palm_out[9], grasp_force, grasp_moment)
    force = plate_out[0:3] + palm_out[0:3] + grasp_force
    torque = plate_out[3:6] + palm_out[3:6] + grasp_moment
    box_steps = box_step(*box_pose[:4], force, torque, box_mass, box_inertia, box_inertia_inv, gravity, dt, box_steps)
    wrench_at_ee_into(plate_out[0:3], plate_out[6:9], position_plate, transform, wrench_ee_true)
    return box_steps


@njit(cache=True)
def _rest(
    arm,
    twist_command,
    dt,
    substeps,
    plate_offset,
    band,
    human,
    box,
    plate,
    palm,
    plate_out,
    palm_out,
    wrench_ee_true,
    trial,
    time_after,
    mu,
    box_steps,
):
    """4. human, 5. physics (substeps), 6. the trial's rule; returns (box steps, the rule's event).
    The groups as world_step makes them: band = (on, low, high), the force band the person waits
    for; human = (state, constants); box = (position, rotation, velocity, omega, half size, mass,
    inertia, its inverse, gravity); plate, palm = a patch's (points, bristles, constants);
    trial = (monitor state, rules)."""
    human_state = human[0]
    t = palm_out[10:13]
    palm_load = np.sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2])
    human_step(*human, dt, palm_out[9], palm_load, plate_out[9], *band, box[1])
    sub_dt = dt / substeps
    for _ in range(substeps):
        box_steps = _physics(
            sub_dt, plate_offset, arm, human, box, plate, palm, plate_out, palm_out, wrench_ee_true, box_steps
        )
    event = monitor_update(
        *trial,
        time_after,
        dt,
        human_state[h.PHASE],
        twist_command,
        human_state[h.GRASP_WEIGHT],
        arm[ERROR] != 0.0,
        box[0],
        box[1],
        human_state[h.POSITION : h.POSITION + 3],
        plate_out,
        palm_out,
        mu,
    )
    return box_steps, event


@njit(cache=True)
def world_step(
    mode,
    sensor_state,
    noise,
    scales,
    wrench_ee,
    law,
    law_state,
    lifting,
    law_constants,
    arm_constants,
    rotations,
    translations,
    axes,
    flange_rotation,
    flange_translation,
    arm,
    twist_command,
    dt,
    substeps,
    plate_offset,
    band_on,
    band_low,
    band_high,
    human_state,
    human_constants,
    box_position,
    box_rotation,
    box_velocity,
    box_omega,
    box_half,
    box_mass,
    box_inertia,
    box_inertia_inv,
    gravity,
    box_steps,
    plate_points,
    plate_bristles,
    plate_constants,
    palm_points,
    palm_bristles,
    palm_constants,
    plate_out,
    palm_out,
    wrench_ee_true,
    monitor,
    rules,
    time_after,
    mu,
):
    """One step from `mode` on (SENSE_CONTROL, ROBOT or REST: see the module's docstring); the
    arguments, in groups: the sensor (world_sense's; read in SENSE_CONTROL only), the built-in law
    (lifting_law_step's first four; SENSE_CONTROL only), the robot (its limits and kinematic
    chain: arm_command_twist's last six; from ROBOT on), then the rest's. Returns (reflex kind,
    joint or axis, value, box steps, the trial rule's event)."""
    if mode == SENSE_CONTROL:
        measure_into(wrench_ee_true, noise, scales, dt, sensor_state, wrench_ee)
        rotation = arm[TRANSFORM : TRANSFORM + 16].reshape((4, 4))[:3, :3].copy()
        lifting_law_step(law, law_state, lifting, law_constants, wrench_ee.copy(), rotation, dt, twist_command)
    kind, j, value = OK, -1, 0.0
    if mode >= ROBOT:
        kind, j, value = arm_command_twist(
            arm, twist_command, dt, arm_constants, rotations, translations, axes, flange_rotation, flange_translation
        )
    box_steps, event = _rest(
        arm,
        twist_command,
        dt,
        substeps,
        plate_offset,
        (band_on, band_low, band_high),
        (human_state, human_constants),
        (
            box_position,
            box_rotation,
            box_velocity,
            box_omega,
            box_half,
            box_mass,
            box_inertia,
            box_inertia_inv,
            gravity,
        ),
        (plate_points, plate_bristles, plate_constants),
        (palm_points, palm_bristles, palm_constants),
        plate_out,
        palm_out,
        wrench_ee_true,
        (monitor, rules),
        time_after,
        mu,
        box_steps,
    )
    return kind, j, value, box_steps, event
