"""The world's 1 kHz step as compiled code (numba): the components' kernels composed, so a step
with a built-in controller is one call from Python (World.step, sim/world.py).

    world_step_builtin = sense (sensor.measure_into)
                       + control (compiled_law.lifting_law_step: SP or patch, steps 0-6)
                       + robot (cartesian_velocity.arm_command_twist: limits, DLS, the compiled
                         Panda kinematics read out of pinocchio's model, sim/robot/panda_kinematics.py)
                       + world_rest
    world_move_rest    = robot (arm_command_twist of a twist from Python: a plug-in's, a node's) + world_rest
    world_rest         = human (human.human_step) + physics (contact.patch_step x 2,
                         human.hand_wrench, box.box_step, sensor.wrench_at_ee_into; substeps)
                         + the trial's rule (monitor.monitor_update)

Every piece is the function the component's own Python method runs (one source per fact), but
for the built-in controllers, whose Python classes are the law of record a student reads and a
sandboxed plug-in imports without numba (sim/controllers/compiled_law.py is tested equal to
them); the state is the components' arrays (sim/state.py), changed in place. With any other controller (a
student's plug-in, a node's external command) or a joint motion, World.step runs `world_sense`,
the controller in Python, then `world_move_rest` (the robot and world_rest): compiled sense, Python
control, compiled robot and rest (a joint motion or a jog: the robot in Python, then world_rest).
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
from sim.robot.cartesian_velocity import ERROR, TRANSFORM, TWIST_BASE, arm_command_twist


@njit(cache=True)
def world_sense(sensor, dt):
    """1. sense: F_ext = the sensor's sample of the true wrench (noise, low-pass) into wrench_ee.
    sensor = (sensor state, this step's noise, scales, wrench_ee_true, wrench_ee): World._sensor_arguments."""
    sensor_state, noise, scales, wrench_ee_true, wrench_ee = sensor
    measure_into(wrench_ee_true, noise, scales, dt, sensor_state, wrench_ee)


@njit(cache=True)
def _physics(dt, plate_offset, arm, human, box, plate, palm, plate_out, palm_out, wrench_ee_true, box_steps):
    """5. physics for dt: plate and palm contacts, the hand's wrench, the box; the true F_ext.
    The groups as world_rest's; returns the box's steps."""
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
def world_rest(
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

    These are the rest's arguments, listed here once: World._rest_arguments builds them in this
    order and world_move_rest passes them on whole. arm and trial (monitor state, rules) are arrays;
    band = (on, low, high) is the force band the person waits for; human = (state, constants);
    box = (position, rotation, velocity, omega, half size, mass, inertia, its inverse, gravity);
    plate, palm = a patch's (points, bristles, constants)."""
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
def world_move_rest(robot, rest):
    """3. robot (arm_command_twist of rest's twist_command: a plug-in's or a node's twist, set from
    Python), then world_rest(*rest). robot = the arm's constants and kinematic chain (World._robot,
    arm_command_twist's last six); rest begins with (arm, twist_command, dt), arm_command_twist's
    first three. Returns (reflex kind, joint or axis, value, box steps, the trial rule's event)."""
    kind, j, value = arm_command_twist(*rest[:3], *robot)
    box_steps, event = world_rest(*rest)
    return kind, j, value, box_steps, event


@njit(cache=True)
def world_step_builtin(sensor, law, robot, rest):
    """A whole step with a built-in controller: sense, control, then world_move_rest.
    sensor = world_sense's group; law = lifting_law_step's first four (the law, its state, the
    lifting vector, its constants). Returns (reflex kind, joint or axis, value, box steps, the
    trial rule's event)."""
    arm, twist_command, dt = rest[:3]
    world_sense(sensor, dt)
    rotation = arm[TRANSFORM : TRANSFORM + 16].reshape((4, 4))[:3, :3].copy()
    wrench_ee = sensor[4]
    lifting_law_step(*law, wrench_ee.copy(), rotation, dt, twist_command)
    return world_move_rest(robot, rest)
