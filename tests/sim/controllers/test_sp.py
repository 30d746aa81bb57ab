"""The SP law, branch by branch, with hand-computed twists (docs/method.md, "The SP controller as hri-lab reconstructs it")."""

import numpy as np
import pytest

from sim.controllers.interface import LiftingParams, ZeroController, start_lifting, stop_lifting
from sim.controllers.sp import SPController

IDENTITY = np.eye(4)


def params(**overrides) -> LiftingParams:
    p = LiftingParams(k_n=0.01, k_t=0.1, k_w=1.0, mu=0.5, alpha=0.8, moment_deadband=0.1, plate_offset=0.02)
    start_lifting(p, 10.0)  # band [10, 15]
    for key, value in overrides.items():
        setattr(p, key, value)
    return p


def twist(wrench, p=None):
    return SPController().twist_ee(np.array(wrench, float), p or params())


def test_start_and_stop_set_the_band():
    p = LiftingParams()
    message = start_lifting(p, 12.0)
    assert (p.f_n_min, p.f_n_max, p.running) == (12.0, 17.0, True)
    assert "12" in message
    message = stop_lifting(p)
    assert (p.f_n_min, p.running) == (0.0, False)
    assert "stopped" in message
    for bad in (-1.0, float("nan"), float("inf")):
        with pytest.raises(ValueError):  # noqa: PT011 - any ValueError is the refusal under test
            start_lifting(p, bad)


def test_below_band_presses_along_plus_n():
    # f_n = 4 < 10: v_n = k_n (10 - 4) = 0.06 m/s along EE +z, nothing else
    assert twist([0, 0, 4, 0, 0, 0]) == pytest.approx([0, 0, 0.06, 0, 0, 0])


def test_inside_band_does_not_move():
    assert twist([1.0, -1.0, 12, 0.02, -0.03, 0.05]) == pytest.approx(np.zeros(6))


def test_above_band_releases_along_minus_n():
    # f_n = 18 > 15: v_n = -k_n (18 - 15) = -0.03 m/s
    assert twist([0, 0, 18, 0, 0, 0]) == pytest.approx([0, 0, -0.03, 0, 0, 0])


def test_inside_the_cone_margin_no_tangential_motion():
    # limit = alpha mu f_n = 0.8 * 0.5 * 12 = 4.8 N; |f_t| = 4.5 -> holds
    assert twist([4.5, 0, 12, 0, 0, 0]) == pytest.approx(np.zeros(6))


def test_slip_moves_against_the_excess_and_raises_the_grip():
    # f_n = 12, f_t = (6, 8, 0), |f_t| = 10 > 4.8: e_t = f_t (1 - 4.8/10) = (3.12, 4.16)
    # v_t = -k_t e_t = (-0.312, -0.416); v_n = k_n (15 - 12) = 0.03 (grip raised toward f_n_max)
    # the measured moment is 0 at the flange, so about p_c: m_c = -p_c x f = (0.02*8, -0.02*6, 0)
    # = (0.16, -0.12, 0), |m_c| = 0.2 -> w = -k_w (1 - 0.1/0.2) m_c = (-0.08, 0.06, 0)
    p = params(v_max=10.0)
    result = twist([6, 8, 12, 0, 0, 0], p)
    assert result == pytest.approx([-0.312, -0.416, 0.03, -0.08, 0.06, 0])


def test_lifting_person_makes_the_robot_follow_up():
    """The person lifts: the plate's friction on the box points down, f_t = -g direction.
    With the EE x axis pointing down (as in the side pose), f_t = +x_ee: the robot must move up."""
    p = params()
    transform = np.eye(4)
    transform[:3, :3] = np.array([[0, -1, 0], [0, 0, 1], [-1, 0, 0]])  # x_ee = -z_base, z_ee = +y_base
    controller = SPController()
    wrench = np.array([8.0, 0, 12, 0, 0, 0])  # 8 N down on the box, beyond 4.8
    for _ in range(1000):  # past the input filter and the rate limiter
        out = controller.step(wrench, transform, p, 1e-3)
    assert out[2] > 0.05  # up in the base frame
    assert out[2] == pytest.approx(0.1 * (8 - 4.8), rel=1e-3)


def test_moment_is_complied_with_outside_the_deadband():
    # m_c = m - p_c x f with p_c = (0, 0, 0.02), f = (0, 0, 12): p_c x f = 0 -> m_c = m = (0.5, 0, 0)
    # w = -k_w (1 - 0.1/0.5) m_c = (-0.4, 0, 0)
    assert twist([0, 0, 12, 0.5, 0, 0]) == pytest.approx([0, 0, 0, -0.4, 0, 0])
    # a tangential force at the plate surface has a moment about the flange but none about p_c:
    # f = (2, 0, 12), m_flange = p_c x f = (0, 0.04, 0) -> m_c = 0: no rotation
    assert twist([2, 0, 12, 0, 0.04, 0]) == pytest.approx(np.zeros(6))
    # below the deadband nothing
    assert twist([0, 0, 12, 0.05, 0, 0]) == pytest.approx(np.zeros(6))


def test_no_tangential_or_rotational_motion_without_contact():
    # f_n = 0.5 N < f_contact: only the approach along +n, noise in f_t and m is ignored
    assert twist([3, -2, 0.5, 0.4, 0.3, 0], params(f_contact=1.0)) == pytest.approx([0, 0, 0.095, 0, 0, 0])


def test_twist_is_rotated_to_the_base_frame():
    """Hand-rotated case: EE rotated by +90 deg about base z: x_ee = +y_b, y_ee = -x_b, z_ee = z_b.
    twist_ee = (v_t = (-0.312, -0.416, 0.03), w = 0) -> base (0.416, -0.312, 0.03)."""
    p = params(v_max=10.0, a_max=1e6, dw_max=1e6, filter_hz=0.0)
    transform = np.eye(4)
    transform[:3, :3] = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    out = SPController().step(np.array([6.0, 8, 12, 0.5, 0, 0]), transform, p, 1e-3)
    # w_ee = -k_w (1 - 0.1/|m_c|) m_c with m_c = (0.5 + 0.02*8, -0.02*6, 0) = (0.66, -0.12, 0)
    m_c = np.array([0.66, -0.12, 0.0])
    w_ee = -(1 - 0.1 / np.linalg.norm(m_c)) * m_c
    assert out[:3] == pytest.approx([0.416, -0.312, 0.03])
    assert out[3:] == pytest.approx([-w_ee[1], w_ee[0], 0.0])


def test_saturation_keeps_the_direction():
    p = params(v_max=0.1)
    result = twist([60, 80, 12, 0, 0, 0], p)
    assert np.linalg.norm(result[:3]) == pytest.approx(0.1)
    assert result[1] / result[0] == pytest.approx(0.416 / 0.312, rel=0.2)


def test_stopped_controller_commands_zero():
    p = params()
    stop_lifting(p)
    controller = SPController()
    out = np.ones(6)
    for _ in range(200):
        out = controller.step(np.array([0.0, 0, 3, 0, 0, 0]), IDENTITY, p, 1e-3)
    assert out == pytest.approx(np.zeros(6))
    assert ZeroController().step(None, None, p, 1e-3) == pytest.approx(np.zeros(6))


def test_rate_limit_bounds_the_change_per_period():
    p = params(a_max=1.0, filter_hz=0.0)
    controller = SPController()
    out = controller.step(np.array([0.0, 0, 0, 0, 0, 0]), IDENTITY, p, 1e-3)
    assert np.linalg.norm(out[:3]) == pytest.approx(1.0 * 1e-3)  # 1 m/s^2 * 1 ms
