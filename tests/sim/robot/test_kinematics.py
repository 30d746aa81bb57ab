"""Panda J^T F (Exercise 8), its least-squares inverse (Exercise 2), the planar arm (Exercise 1)."""

import numpy as np
import pytest

from sim.robot import planar_arm
from sim.robot.panda import READY_Q, SIDE_Q, PandaModel


@pytest.fixture(scope="module")
def panda():
    return PandaModel()


def random_q(model, rng):
    return rng.uniform(model.q_min, model.q_max)


def test_virtual_work_identity(panda):
    """tau . qdot = F . (J qdot): the power of the joint torques equals the power of the wrench."""
    rng = np.random.default_rng(1)
    for _ in range(50):
        q = random_q(panda, rng)
        qdot = rng.normal(size=7)
        wrench = rng.normal(size=6) * [10, 10, 10, 1, 1, 1]
        tau = panda.torques_from_wrench(q, wrench)
        twist = panda.jacobian_base(q) @ qdot
        assert tau @ qdot == pytest.approx(wrench @ twist, rel=1e-9, abs=1e-9)


def test_jacobian_matches_finite_difference_of_fk(panda):
    """The base-frame flange Jacobian predicts the FK motion (linear part and rotation)."""
    rng = np.random.default_rng(2)
    q = READY_Q.copy()
    qdot = rng.normal(size=7)
    h = 1e-6
    t0 = panda.transform_ee_to_base(q).copy()
    t1 = panda.transform_ee_to_base(q + h * qdot).copy()
    twist = panda.jacobian_base(q) @ qdot
    assert (t1[:3, 3] - t0[:3, 3]) / h == pytest.approx(twist[:3], abs=1e-4)
    skew = (t1[:3, :3] - t0[:3, :3]) / h @ t0[:3, :3].T  # dR R^T = [w]x
    assert [skew[2, 1], skew[0, 2], skew[1, 0]] == pytest.approx(twist[3:], abs=1e-4)


def test_torques_of_a_pure_force_are_lever_arms(panda):
    """A vertical force at the flange loads joint 1 (vertical axis) not at all; joint 2's torque is
    the moment of the force about joint 2's axis: tau_2 = a . ((p_ee - p_2) x f)."""
    q = READY_Q.copy()
    wrench = np.array([0.0, 0.0, -10.0, 0.0, 0.0, 0.0])
    tau = panda.torques_from_wrench(q, wrench)
    assert tau[0] == pytest.approx(0.0, abs=1e-9)
    p_ee = panda.transform_ee_to_base(q)[:3, 3]
    joint2 = np.array([0.0, 0.0, 0.333])  # panda_joint2 origin in the base frame
    axis2 = np.array([0.0, 1.0, 0.0])  # joint 2 turns about base +y at q1 = 0
    expected = axis2 @ np.cross(p_ee - joint2, wrench[:3])
    assert tau[1] == pytest.approx(expected, rel=1e-9)


def test_least_squares_wrench_recovers_the_wrench(panda):
    rng = np.random.default_rng(3)
    q = SIDE_Q.copy()
    wrench = rng.normal(size=6)
    estimate, residual = panda.wrench_from_torques(q, panda.torques_from_wrench(q, wrench))
    assert estimate == pytest.approx(wrench, abs=1e-9)
    assert residual == pytest.approx(0.0, abs=1e-9)
    # a torque in the null space of J^T cannot come from a flange wrench: it is left over
    _, _, vt = np.linalg.svd(panda.jacobian_base(q))
    null = vt[-1]  # J null @ = 0  <=>  null is orthogonal to the rows of J, i.e. to range(J^T)
    _, residual = panda.wrench_from_torques(q, panda.torques_from_wrench(q, wrench) + 2.0 * null)
    assert residual == pytest.approx(2.0, rel=1e-6)


# Exercise 1, by hand. theta_i = q_1 + ... + q_i, links of 1 m:
#   tau_j = sum_{i>=j} (-sin(theta_i) f_x + cos(theta_i) f_y)
# q_I  = (0, 0, 0):          sin = (0, 0, 0), cos = (1, 1, 1)  -> tau = f_y (3, 2, 1)
# q_II = (pi/2, -pi/2, pi/2): theta = (pi/2, 0, pi/2), sin = (1, 0, 1), cos = (0, 1, 0)
#                             -> tau = -f_x (2, 1, 1) + f_y (1, 1, 0)
Q_I = [0.0, 0.0, 0.0]
Q_II = [np.pi / 2, -np.pi / 2, np.pi / 2]
F_I, F_II, F_III = [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]
CASES = [
    (Q_I, F_I, [0.0, 0.0, 0.0]),
    (Q_I, F_II, [3.0, 2.0, 1.0]),
    (Q_I, F_III, [3.0, 2.0, 1.0]),
    (Q_II, F_I, [-2.0, -1.0, -1.0]),
    (Q_II, F_II, [1.0, 1.0, 0.0]),
    (Q_II, F_III, [-1.0, 0.0, -1.0]),
]


@pytest.mark.parametrize(("q", "force", "expected"), CASES)
def test_planar_arm_torques_by_hand(q, force, expected):
    assert planar_arm.torques(q, force) == pytest.approx(expected, abs=1e-12)


def test_planar_arm_kinematics_by_hand():
    assert planar_arm.forward_kinematics(Q_I) == pytest.approx([3.0, 0.0, 0.0])
    assert planar_arm.forward_kinematics(Q_II) == pytest.approx([1.0, 2.0, np.pi / 2])
    # Jacobian = finite difference of the forward kinematics
    q = np.array([0.3, -0.7, 1.1])
    jac = np.column_stack(
        [(planar_arm.forward_kinematics(q + 1e-7 * e) - planar_arm.forward_kinematics(q)) / 1e-7 for e in np.eye(3)]
    )
    assert planar_arm.jacobian(q) == pytest.approx(jac, abs=1e-6)
    with pytest.raises(ValueError):  # noqa: PT011 - any ValueError is the refusal under test
        planar_arm.torques(Q_I, [1.0])
