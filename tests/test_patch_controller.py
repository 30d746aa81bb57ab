"""The patch controller's contact reasoning, against hand-computed cases, and its moment law."""
import numpy as np
import pytest

from sim.box import Box, BoxParams
from sim.contact import ContactParams, PatchContact, PatchGeometry
from sim.controller import LiftingParams, start_lifting
from sim.patch_controller import PatchController, patch_grip
from sim.sensor import wrench_at_ee
from sim.sp_controller import SPController

D = 0.02  # plate offset (m)
R_EQ = PatchGeometry(0.10, 0.10).mean_radius


def test_pure_normal_force_at_the_centre():
    grip = patch_grip(np.array([0, 0, 10.0, 0, 0, 0]), D, 0.5, R_EQ)
    assert grip.cop == pytest.approx([0, 0]) and grip.m_n == pytest.approx(0) and grip.limit_surface == pytest.approx(0)


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
    assert R_EQ == pytest.approx(0.03788, abs=1e-4)
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


def test_patch_holds_a_moment_the_patch_can_hold_sp_complies():
    # 0.2 Nm about EE x at f_n = 12 N: the plate holds up to 0.7 * 0.05 * 12 = 0.42 Nm
    wrench = np.array([0, 0, 12.0, 0.2, 0, 0])
    assert np.linalg.norm(PatchController().twist_ee(wrench, params())[3:]) == pytest.approx(0.0)
    assert np.linalg.norm(SPController().twist_ee(wrench, params())[3:]) > 0.05
    # beyond what it can hold it complies with the excess only: w_x = -k_w (0.6 - 0.42)
    w = PatchController().twist_ee(np.array([0, 0, 12.0, 0.6, 0, 0]), params())[3:]
    assert w == pytest.approx([-(0.6 - 0.42), 0, 0], abs=1e-9)


def test_patch_follows_the_person_like_sp_beyond_the_limit_surface():
    # the person lifts: 8 N of friction down (EE +x) at 12 N, no torsion: beyond 0.8 * 0.5 * 12 = 4.8 N
    v = PatchController().twist_ee(np.array([8.0, 0, 12.0, 0, 0, 0]), params())[:3]
    assert v[0] == pytest.approx(-0.1 * (8 - 4.8))
    assert v[2] > 0  # and the grip is raised
