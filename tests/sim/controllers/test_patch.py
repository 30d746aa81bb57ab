"""The patch controller's contact reasoning, against hand-computed cases, and its moment law."""

import numpy as np
import pytest

from sim.controllers.interface import LiftingParams, start_lifting
from sim.controllers.patch import PatchController, kern_ratio, patch_grip
from sim.controllers.sp import SPController
from sim.physics.box import Box, BoxParams
from sim.physics.contact import ContactParams, PatchContact, PatchGeometry
from sim.physics.sensor import wrench_at_ee
from sim.robot.plate import Plate

D = 0.02  # plate offset (m)
R_EQ = PatchGeometry(0.10, 0.10).mean_radius


def test_pure_normal_force_at_the_centre():
    grip = patch_grip(np.array([0, 0, 10.0, 0, 0, 0]), D, 0.5, R_EQ)
    assert grip.cop == pytest.approx([0, 0])
    assert grip.m_n == pytest.approx(0)
    assert grip.limit_surface == pytest.approx(0)


def test_offset_force():
    """10 N pushed at (0.02, -0.01) on the plate: at the flange m = r x f with r = (0.02, -0.01, d)
    = (-0.1, -0.2, 0) Nm; p_x = (d f_x - m_y)/f_z = 0.02, p_y = (d f_y + m_x)/f_z = -0.01."""
    r, f = np.array([0.02, -0.01, D]), np.array([0, 0, 10.0])
    m = np.cross(r, f)
    assert m == pytest.approx([-0.1, -0.2, 0.0])
    grip = patch_grip(np.concatenate((f, m)), D, 0.5, R_EQ)
    assert grip.cop == pytest.approx([0.02, -0.01])
    assert grip.m_c == pytest.approx([-0.1, -0.2, 0.0])  # about the plate centre = p x f


def test_tangential_force_at_the_surface_is_not_an_offset():
    # f = (2, 0, 10) at the plate centre: m at the flange = p_c x f = (0, 0.04, 0); cop stays (0, 0)
    grip = patch_grip(np.array([2.0, 0, 10, 0, 0.04, 0]), D, 0.5, R_EQ)
    assert grip.cop == pytest.approx([0, 0], abs=1e-12)
    assert grip.limit_surface == pytest.approx((2 / 5) ** 2)  # (|f_t| / (mu f_n))^2


def test_pure_torsion():
    # m_z = 0.1 Nm, f_n = 10 N, mu = 0.5: s = (0.1 / (5 r_eq))^2, r_eq = mean point distance (0.0379 m)
    assert pytest.approx(0.03788, abs=1e-4) == R_EQ
    grip = patch_grip(np.array([0, 0, 10.0, 0, 0, 0.1]), D, 0.5, R_EQ)
    assert grip.m_n == pytest.approx(0.1)
    assert grip.limit_surface == pytest.approx((0.1 / (5 * R_EQ)) ** 2)


def test_centre_of_pressure_agrees_with_the_contact_model():
    """A tilted plate pressed on a box: the contact model's own centre of pressure (from its
    point forces) and the one the controller reads from F_ext at the flange are the same point."""
    plate = PatchContact(PatchGeometry(0.10, 0.10), ContactParams())
    box = Box(BoxParams(), np.zeros(3))
    rotation = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0]])
    from sim.spatial import rotation_exp

    rotation = rotation @ rotation_exp(np.array([0.004, -0.003, 0.0]))
    centre = np.array([0.0, -0.1 + 0.0006, 0.0])
    result = plate.step(rotation, centre, np.zeros(3), np.zeros(3), box.pose(), 1e-3)
    transform = np.eye(4)
    transform[:3, :3] = rotation
    transform[:3, 3] = centre - rotation[:, 2] * D  # the flange behind the plate
    wrench = wrench_at_ee(result.force_box, result.moment_patch, centre, transform)
    grip = patch_grip(wrench, D, 0.5, R_EQ)
    assert grip.cop == pytest.approx(result.centre_of_pressure, abs=2e-4)
    assert np.linalg.norm(grip.cop) > 0.005  # really off-centre


def params() -> LiftingParams:
    p = LiftingParams(filter_hz=0.0)
    start_lifting(p, 10.0)
    return p


def test_kern_ratio():
    """k = 6|p_x|/W + 6|p_y|/H on the 0.10 x 0.10 m plate: the middle third along one axis is
    |p| <= W/6 = 16.7 mm; a corner of the kern (k = 1) is shared between the axes."""
    plate = Plate()
    assert kern_ratio(np.array([0.10 / 6, 0.0]), plate) == pytest.approx(1.0)
    assert kern_ratio(np.array([0.0, -0.10 / 6]), plate) == pytest.approx(1.0)
    assert kern_ratio(np.array([0.01, 0.01]), plate) == pytest.approx(1.2)  # a square's corner is outside


def test_patch_holds_a_moment_inside_the_kern_sp_complies():
    # 0.15 Nm about EE x at f_n = 12 N: p_y = 0.15/12 = 12.5 mm, k = 6 * 0.0125 / 0.1 = 0.75 <= 1: held
    wrench = np.array([0, 0, 12.0, 0.15, 0, 0])
    assert np.linalg.norm(PatchController().twist_ee(wrench, params())[3:]) == pytest.approx(0.0)
    assert np.linalg.norm(SPController().twist_ee(wrench, params())[3:]) > 0.04
    # beyond the kern it complies with the excess only: 0.6 Nm -> k = 3, held = 1/3 (0.2 Nm = the
    # kern's 12 N x 0.1 m / 6), w_x = -k_w (1 - 1/3) 0.6 = -0.4 rad/s
    w = PatchController().twist_ee(np.array([0, 0, 12.0, 0.6, 0, 0]), params())[3:]
    assert w == pytest.approx([-0.4, 0, 0], abs=1e-9)


def test_tipping_along_a_diagonal_is_brought_back_to_the_kern_boundary():
    # p = (10, 10) mm at 12 N: m_c,xy = (p_y f_n, -p_x f_n) = (0.12, -0.12) Nm, k = 1.2: the
    # radial projection onto the kern keeps 1/1.2 of it and turns with the rest, same direction
    wrench = np.array([0, 0, 12.0, 0.12, -0.12, 0])
    w = PatchController().twist_ee(wrench, params())[3:]
    assert w == pytest.approx([-(1 - 1 / 1.2) * 0.12, (1 - 1 / 1.2) * 0.12, 0], abs=1e-9)


def test_moments_below_the_noise_floor_are_held_even_at_a_light_grip():
    # at f_n = 2 N the kern holds only 2 * 0.1 / 6 = 0.033 Nm; 0.08 Nm is under the 0.1 Nm deadband
    assert PatchController().twist_ee(np.array([0, 0, 2.0, 0.08, 0, 0]), params())[3:] == pytest.approx(np.zeros(3))
    # 0.2 Nm at 2 N (k = 6): the deadband (0.1 Nm) is the larger hold: w_x = -(1 - 0.1/0.2) 0.2 = -0.1
    w = PatchController().twist_ee(np.array([0, 0, 2.0, 0.2, 0, 0]), params())[3:]
    assert w == pytest.approx([-0.1, 0, 0], abs=1e-9)


def test_patch_follows_the_person_like_sp_beyond_the_limit_surface():
    # the person lifts: 6 N of friction down (EE +x) at 12 N, no torsion: beyond alpha mu f_n =
    # 0.5 * 0.5 * 12 = 3 N (the default alpha 0.5), v_x = -k_t (6 - 3) = -0.3 m/s (under v_max)
    wrench = np.array([6.0, 0, 12.0, 0, D * 6.0, 0])  # applied at the plate centre: m = p_c x f
    v = PatchController().twist_ee(wrench, params())[:3]
    assert v[0] == pytest.approx(-0.1 * (6 - 3.0))
    assert v[2] > 0  # and the grip is raised
    # without torsion the limit-surface law is exactly SP's cone law
    assert PatchController().twist_ee(wrench, params())[:3] == pytest.approx(
        SPController().twist_ee(wrench, params())[:3]
    )


def test_torsion_beyond_the_limit_surface_turns_about_the_normal_and_raises_the_grip():
    # m_n = 0.3 Nm at 12 N, no f_t: m_n' = 0.3 - 0.025 = 0.275 (deadband), s = (0.275 / (6 r_eq))^2;
    # = 1.46 > alpha^2 = 0.25; excess e = 1 - 0.5 / sqrt(s) = 0.59, w_z = -k_w e m_n' = -0.16 rad/s,
    # no tangential motion, grip raised
    wrench = np.array([0, 0, 12.0, 0, 0, 0.3])
    s = (0.275 / (0.5 * 12 * R_EQ)) ** 2
    assert s > 0.5**2
    twist = PatchController().twist_ee(wrench, params())
    assert twist[5] == pytest.approx(-(1 - 0.5 / np.sqrt(s)) * 0.275)
    assert twist[:2] == pytest.approx([0, 0])
    assert twist[2] > 0


def test_torsion_the_patch_holds_and_torsion_noise_do_not_move_it():
    # 0.1 Nm at 12 N: s = (0.075 / (6 r_eq))^2 = 0.11 < alpha^2 = 0.25: held (SP would turn with it)
    assert PatchController().twist_ee(np.array([0, 0, 12.0, 0, 0, 0.1]), params()) == pytest.approx(np.zeros(6))
    assert SPController().twist_ee(np.array([0, 0, 12.0, 0, 0, 0.12]), params())[5] < 0
    # f_t just inside the cone margin (2.9 < alpha mu f_n = 3 N) plus torsion noise under the deadband: no motion
    wrench = np.array([2.9, 0, 12.0, 0, D * 2.9, 0.02])
    assert PatchController().twist_ee(wrench, params()) == pytest.approx(np.zeros(6))


def test_torsion_and_friction_share_the_limit_surface():
    # f_t = 2.4 N (inside the cone margin alpha mu f_n = 3 N alone: s_f = 0.16) with m_n = 0.1 Nm
    # (m_n' = 0.075, inside alone: s_m = 0.11): together s = (2.4/6)^2 + (0.075/(6 r_eq))^2 = 0.16 + 0.11
    # = 0.27 > alpha^2 = 0.25: both follow with the same excess e = 1 - 0.5 / sqrt(s) = 0.036
    wrench = np.array([2.4, 0, 12.0, 0, D * 2.4, 0.1])
    s = (2.4 / 6) ** 2 + (0.075 / (6 * R_EQ)) ** 2
    assert max((2.4 / 6) ** 2, (0.075 / (6 * R_EQ)) ** 2) < 0.5**2 < s
    e = 1 - 0.5 / np.sqrt(s)
    twist = PatchController().twist_ee(wrench, params())
    assert twist[0] == pytest.approx(-0.1 * e * 2.4)
    assert twist[5] == pytest.approx(-e * 0.075)
    assert twist[3:5] == pytest.approx([0, 0], abs=1e-12)  # the friction at the surface is no tipping moment
