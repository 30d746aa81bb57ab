"""franka-like Cartesian velocity interface: tracking, limits as reflexes, recovery."""

import numpy as np
import pytest

from sim.robot.cartesian_velocity import CartesianVelocityInterface
from sim.robot.panda import SIDE_Q, PandaModel

DT = 1e-3


@pytest.fixture
def arm():
    return CartesianVelocityInterface(PandaModel(), SIDE_Q)


def ramp(arm, twist, steps=100):
    """Ramp to `twist` within the acceleration limits, then hold it for `steps` periods."""
    twist = np.asarray(twist, float)
    for s in range(1, 201):
        arm.command_twist(twist * s / 200, DT)
    for _ in range(steps):
        arm.command_twist(twist, DT)


def test_small_twist_is_followed(arm):
    start = arm.transform_ee_to_base[:3, 3].copy()
    ramp(arm, [0.0, 0.0, 0.05, 0.0, 0.0, 0.0], steps=1000)
    moved = arm.transform_ee_to_base[:3, 3] - start
    # 0.05 m/s for 1 s plus the 0.2 s ramp (area 0.005 m)
    assert moved == pytest.approx([0.0, 0.0, 0.055], abs=5e-4)
    assert arm.error is None
    assert arm.twist_base == pytest.approx([0, 0, 0.05, 0, 0, 0], abs=1e-3)


def test_cartesian_velocity_limit_is_a_reflex_and_recover_clears_it(arm):
    ramp(arm, [0.0, 0.0, 0.05, 0, 0, 0], steps=10)
    arm.command_twist(np.array([0.0, 0.0, 1.8, 0, 0, 0]), DT)  # 1.8 > 1.7 m/s
    assert arm.error is not None
    assert "cartesian velocity limit" in arm.error
    q_stopped = arm.q.copy()
    # while in error nothing moves, whatever is commanded
    for _ in range(50):
        arm.command_twist(np.array([0.0, 0.0, 0.01, 0, 0, 0]), DT)
    assert arm.q == pytest.approx(q_stopped)
    assert arm.qdot == pytest.approx(np.zeros(7))
    arm.recover()
    assert arm.error is None
    ramp(arm, [0.0, 0.0, 0.02, 0, 0, 0], steps=10)
    assert arm.error is None
    assert not np.allclose(arm.q, q_stopped)


def test_angular_velocity_limit(arm):
    arm.command_twist(np.array([0, 0, 0, 2.6, 0, 0.0]), DT)
    assert "cartesian velocity limit" in arm.error


def test_acceleration_jump_is_a_reflex(arm):
    # from rest to 0.1 m/s in one period = 100 m/s^2 > 13 m/s^2
    arm.command_twist(np.array([0.1, 0, 0, 0, 0, 0.0]), DT)
    assert "cartesian acceleration limit" in arm.error


def test_joint_position_limit_is_a_reflex(arm):
    """Drive joint 4 into its upper limit (-0.0698 rad) with joint velocities."""
    q4_max = arm.model.q_max[3]
    qdot = np.zeros(7)
    for _ in range(20000):
        qdot[3] = min(qdot[3] + 5.0 * DT, 1.0)
        arm.command_joint_velocity(qdot, DT)
        if arm.error:
            break
    assert arm.error is not None
    assert "joint position limit: joint 4" in arm.error
    assert arm.q[3] <= q4_max
    assert arm.qdot == pytest.approx(np.zeros(7))


def test_joint_velocity_limit_is_a_reflex(arm):
    qdot = np.zeros(7)
    for _ in range(1000):
        qdot[0] += 10.0 * DT  # 10 rad/s^2 < 15: joint 1 crosses 2.175 rad/s after ~0.22 s
        arm.command_joint_velocity(qdot, DT)
        if arm.error:
            break
    assert "joint velocity limit: joint 1" in arm.error


def test_invalid_commands_stop_the_robot(arm):
    arm.command_twist(np.array([np.nan, 0, 0, 0, 0, 0]), DT)
    assert "invalid command" in arm.error
    arm.recover()
    arm.command_twist(np.array([0.0, 0.0]), DT)
    assert "invalid command" in arm.error
    assert np.all(np.isfinite(arm.q))


def test_after_recovery_the_posture_term_ramps_instead_of_re_tripping():
    """Far from the rest posture (the elbow drifted while following), recover() leaves the robot
    at rest; the null-space term k (q_rest - q) alone would jump qdot beyond the joint acceleration
    limit in one period and trip again, forever. It is ramped: no reflex, the elbow comes back."""

    def drifted(ramp):
        arm = CartesianVelocityInterface(PandaModel(), SIDE_Q)
        arm.null_space_ramp = ramp
        arm.q_rest = arm.q + np.array([0.3, 0.0, -0.3, 0.0, 0.3, 0.0, 0.3])
        arm.error = "a reflex before"
        arm.recover()
        return arm

    unramped = drifted(np.inf)
    unramped.command_twist(np.zeros(6), DT)
    assert unramped.error is not None
    assert "joint acceleration limit" in unramped.error
    arm = drifted(CartesianVelocityInterface.null_space_ramp)
    q_start, ee_start = arm.q.copy(), arm.transform_ee_to_base[:3, 3].copy()
    for _ in range(1000):
        arm.command_twist(np.zeros(6), DT)
        assert arm.error is None
    assert np.linalg.norm(arm.q - q_start) > 0.05
    assert arm.transform_ee_to_base[:3, 3] == pytest.approx(ee_start, abs=2e-3)  # the null space does not move the EE
