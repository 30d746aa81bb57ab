"""sim/robot/joint_trajectory.py: a minimum-jerk joint motion lasts as long as its joints' velocity and
acceleration limits need (hand-computed durations), its commands stay within the acceleration limits
at every distance, and a move to start shortly after a teleop jog (the dashboard's two buttons, one
after the other) gets there without a reflex."""

import numpy as np
import pytest

from sim.robot.joint_trajectory import ACCELERATION_SHARE, JointTrajectory
from sim.robot.panda import JOINT_ACCELERATION_LIMITS, SIDE_Q
from sim.robot.teleop import key_twist
from sim.world import World

DT = 0.001  # s, the control period


def moved(joint: int, distance: float) -> np.ndarray:
    goal = SIDE_Q.copy()
    goal[joint] += distance
    return goal


def test_a_motion_lasts_what_its_velocity_or_its_acceleration_limit_needs():
    # 1 rad of joint 1 at 0.5 rad/s: T = 1.875 * 1.0 / 0.5 = 3.75 s (its acceleration alone: sqrt(5.77 / 7.5) = 0.88 s)
    assert JointTrajectory(SIDE_Q, moved(0, 1.0)).duration == pytest.approx(3.75)
    # 0.0256 rad of joint 4 (limit 12.5 rad/s^2, half of it used): T = sqrt(5.7735 * 0.0256 / 6.25) = 0.1538 s,
    # where its velocity alone gives 1.875 * 0.0256 / 0.5 = 0.096 s (a peak of 14.8 rad/s^2: a reflex)
    assert JointTrajectory(SIDE_Q, moved(3, -0.0256)).duration == pytest.approx(0.1538, abs=1e-4)
    # 1 mrad: sqrt(5.7735 * 0.001 / 6.25) = 0.030 s, less than the shortest motion, 0.1 s
    assert JointTrajectory(SIDE_Q, moved(3, 0.001)).duration == pytest.approx(0.1)


@pytest.mark.parametrize("joint", range(7))
def test_every_distance_stays_within_the_joints_acceleration_limits(joint):
    for distance in np.geomspace(1e-3, 1.5, 12):
        motion = JointTrajectory(SIDE_Q, moved(joint, distance))
        q, qdot, peak = SIDE_Q.copy(), np.zeros(7), np.zeros(7)
        while not motion.done:
            command = motion.command(q, DT)
            peak = np.maximum(peak, np.abs(command - qdot) / DT)
            q, qdot = q + command * DT, command
        assert q == pytest.approx(moved(joint, distance), abs=1e-3)  # there, as tests/sim/test_world.py checks it
        # at most the share of the limit the reference uses (the discrete steps add a little)
        assert np.all(peak <= 1.05 * ACCELERATION_SHARE * JOINT_ACCELERATION_LIMITS), (distance, peak)


def test_move_to_start_shortly_after_a_jog_gets_there_without_a_reflex():
    """117 ms into the 'w' key's jog (the lab's 0.1 m/s): the brake, then a 0.026 rad motion of joint 4
    that took 0.1 s at 0.5 rad/s and stopped the robot with 'joint acceleration limit: joint 4 at
    12.7 rad/s^2 (limit 12.5)'."""
    world = World()
    world.start_jog(key_twist("w", 0.1, 0.1))
    for _ in range(117):
        world.step()
    world.move_to_start()
    while world.motion is not None:
        world.step()
        assert world.error is None
    assert world.arm.q == pytest.approx(SIDE_Q, abs=1e-3)
