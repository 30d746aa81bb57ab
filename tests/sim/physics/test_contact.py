"""Spring contact model: hand-computed forces, squeeze and slip of the box, NaN-free motion."""

import numpy as np
import pytest

from sim.physics.box import GRAVITY, Box, BoxParams
from sim.physics.contact import ContactParams, PatchContact, PatchGeometry
from sim.spatial import rotation_exp

HALF = 0.1  # half size of the default box (m)
PLATE = PatchGeometry(0.10, 0.10, 6, 6)
PALM = PatchGeometry(0.08, 0.08, 5, 5)
# patch frames: the plate looks along +y (its z), the palm along -y
R_PLATE = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0]])  # columns: x=-z, y=-x, z=+y
R_PALM = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, -1.0], [-1.0, 0.0, 0.0]])  # columns: x=-z, y=+x, z=-y
ZERO = np.zeros(3)


def box_at_origin(mass=1.0) -> Box:
    return Box(BoxParams(mass=mass), np.zeros(3))


def test_flat_press_gives_k_times_depth_at_the_centre():
    """All 36 points at depth d: f_n = K d, centre of pressure (0, 0), no moment, force along +y."""
    params = ContactParams(normal_stiffness=2.0e4)
    plate = PatchContact(PLATE, params)
    depth = 0.0005
    result = plate.step(R_PLATE, np.array([0.0, -HALF + depth, 0.0]), ZERO, ZERO, box_at_origin().pose(), 1e-3)
    assert result.points_in_contact == 36
    assert result.normal_force == pytest.approx(2.0e4 * depth)  # 10 N
    assert result.force_box == pytest.approx([0.0, 10.0, 0.0])
    assert result.centre_of_pressure == pytest.approx([0.0, 0.0], abs=1e-12)
    assert result.moment_patch == pytest.approx(ZERO, abs=1e-12)
    # about the box centre the push acts through the centre as well
    assert result.torque_box == pytest.approx(ZERO, abs=1e-12)


def test_tilted_plate_shifts_the_centre_of_pressure_to_the_pressed_edge():
    """Depth d(y) = d0 + theta y_p (plate tilted about its x axis by theta): by hand,
    f_n = K d0, cop_y = theta sum(y_i^2) / (N d0) = theta * 8.102e-4 m^2 / d0 for the 6x6 grid
    (y_i = +-0.00833, +-0.025, +-0.04167 m), and the moment about the plate centre is cop x f."""
    k = 2.0e4
    plate = PatchContact(PLATE, ContactParams(normal_stiffness=k))
    d0, theta = 0.0005, 0.005
    # turning the plate by +theta about its own x axis moves its +y_p edge along +z_p, into the box
    rotation = R_PLATE @ rotation_exp(np.array([theta, 0.0, 0.0]))
    result = plate.step(rotation, np.array([0.0, -HALF + d0, 0.0]), ZERO, ZERO, box_at_origin().pose(), 1e-3)
    mean_y2 = (0.1 / 12) ** 2 * (1 + 9 + 25) / 3  # (h/12)^2 (1^2 + 3^2 + 5^2) / 3
    assert mean_y2 == pytest.approx(8.102e-4, rel=1e-3)
    expected_cop = np.sin(theta) * mean_y2 / d0
    assert result.normal_force == pytest.approx(k * d0, rel=1e-3)
    assert result.centre_of_pressure[0] == pytest.approx(0.0, abs=1e-9)
    assert result.centre_of_pressure[1] == pytest.approx(expected_cop, rel=1e-2)
    assert result.centre_of_pressure[1] > 0.005  # toward the pressed (+y_p) edge
    # moment about the plate centre = cop (in world) x f: the push is off-centre
    cop_world = rotation[:, 1] * result.centre_of_pressure[1]
    assert result.moment_patch == pytest.approx(np.cross(cop_world, result.force_box), abs=1e-4)


def squeeze_rig(normal_force: float, mu: float, seconds: float, mass: float = 1.0):
    """Box squeezed between a fixed plate (-y face) and a fixed palm (+y face) with ~normal_force;
    returns the box trajectory (positions per step)."""
    plate_params = ContactParams(normal_stiffness=2.0e4, mu=mu)
    palm_params = ContactParams(normal_stiffness=2.0e4, mu=mu)
    plate, palm = PatchContact(PLATE, plate_params), PatchContact(PALM, palm_params)
    depth = normal_force / 2.0e4
    plate_pos = np.array([0.0, -HALF + depth, 0.0])
    palm_pos = np.array([0.0, HALF - depth, 0.0])
    box = box_at_origin(mass)
    dt = 1e-3
    positions = []
    for _ in range(int(seconds / dt)):
        pose = box.pose()
        a = plate.step(R_PLATE, plate_pos, ZERO, ZERO, pose, dt)
        b = palm.step(R_PALM, palm_pos, ZERO, ZERO, pose, dt)
        box.step(a.force_box + b.force_box, a.torque_box + b.torque_box, dt)
        positions.append(box.position.copy())
    return np.array(positions), a, b


def test_squeezed_box_stays_within_a_millimetre_for_ten_seconds():
    """f_n = 15 N on both sides, mu = 0.6: the two cones hold 18 N > m g; no creep."""
    positions, plate, palm = squeeze_rig(15.0, 0.6, 10.0)
    drift = np.linalg.norm(positions - positions[0], axis=1)
    assert drift.max() < 1e-3
    # after settling it does not move at all (stick, no creep)
    assert np.linalg.norm(positions[-1] - positions[1000]) < 1e-5
    # and each contact carries about half of the weight, inside its cone
    assert plate.tangential_force[2] + palm.tangential_force[2] == pytest.approx(-GRAVITY[2], rel=1e-3)
    assert plate.points_slipping == 0
    assert palm.points_slipping == 0


def test_box_squeezed_below_mg_over_2mu_slides_down():
    """f_n = 0.8 m g / (2 mu): the friction can hold only 80 % of the weight -> the box slides."""
    mu = 0.5
    f_n = 0.8 * 9.81 / (2 * mu)
    positions, _, _ = squeeze_rig(f_n, mu, 1.0)
    fall = positions[0, 2] - positions[-1, 2]
    # net force >= 0.2 m g while sliding: s >= 0.5 * 0.2 g t^2 ~ 0.98 m in 1 s minus the stick phase
    assert fall > 0.2
    assert positions[-1, 2] < positions[-100, 2]  # still sliding down


def test_no_nan_in_1e5_steps_of_random_motion():
    """Plate and palm move randomly (smooth random velocities) around a box that is squeezed,
    dropped, hit and released; every force and state stays finite."""
    rng = np.random.default_rng(7)
    plate = PatchContact(PLATE, ContactParams())
    palm = PatchContact(PALM, ContactParams(normal_stiffness=1e4, mu=1.0))
    box = box_at_origin()
    plate_pos, palm_pos = np.array([0.0, -HALF + 5e-4, 0.0]), np.array([0.0, HALF - 5e-4, 0.0])
    r_plate, r_palm = R_PLATE.copy(), R_PALM.copy()
    v_plate, w_plate, v_palm, w_palm = (np.zeros(3) for _ in range(4))
    dt, steps = 1e-3, 100_000
    kicks = rng.normal(size=(steps, 4, 3)) * np.sqrt(dt) * np.array([[0.5], [0.5], [2.0], [2.0]])  # drawn at once
    side = np.array([0.0, HALF, 0.0])
    for i in range(steps):
        # Ornstein-Uhlenbeck velocities, pulled back toward the box so contacts keep happening
        v_plate += -5 * v_plate * dt + kicks[i, 0] + (box.position - side - plate_pos) * dt * 20
        v_palm += -5 * v_palm * dt + kicks[i, 1] + (box.position + side - palm_pos) * dt * 20
        w_plate += -5 * w_plate * dt + kicks[i, 2]
        w_palm += -5 * w_palm * dt + kicks[i, 3]
        plate_pos = plate_pos + v_plate * dt
        palm_pos = palm_pos + v_palm * dt
        r_plate = rotation_exp(w_plate * dt) @ r_plate
        r_palm = rotation_exp(w_palm * dt) @ r_palm
        pose = box.pose()
        a = plate.step(r_plate, plate_pos, v_plate, w_plate, pose, dt)
        b = palm.step(r_palm, palm_pos, v_palm, w_palm, pose, dt)
        box.step(a.force_box + b.force_box, a.torque_box + b.torque_box, dt)
        if i % 1000 == 0:
            state = np.concatenate(
                (
                    box.position,
                    box.velocity,
                    box.angular_velocity,
                    box.rotation.ravel(),
                    a.force_box,
                    a.torque_box,
                    b.force_box,
                    b.torque_box,
                    plate.bristles.ravel(),
                )
            )
            assert np.all(np.isfinite(state)), f"non-finite state at step {i}"
    assert np.all(np.isfinite(box.position))
    assert np.all(np.isfinite(box.rotation))
    assert np.linalg.det(box.rotation) == pytest.approx(1.0, abs=1e-6)
