"""What the views draw with (app/view/scene.py): the friction cone's shape, the Panda where the
simulation has it, rotations as viser's quaternions."""

import numpy as np
import pinocchio as pin
import pytest
import viser

from sim.robot.panda import PandaModel

from app.view.scene import NOT_SHOWN, PandaUrdf, cone_mesh, wxyz


def test_friction_cone_opening_is_mu():
    vertices, faces = cone_mesh(0.5, height=0.1)
    radius = np.linalg.norm(vertices[1:, :2], axis=1)
    assert radius == pytest.approx(0.05, rel=1e-6)  # tan(half angle) = r / h = mu
    assert np.all(vertices[1:, 2] == pytest.approx(0.1)) and faces.shape == (24, 3)


@pytest.fixture(scope="module")
def server():
    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    yield server
    server.stop()


@pytest.mark.parametrize("light", [True, False])
def test_the_panda_is_drawn_where_the_simulation_puts_it(server, light):
    """Each link drawn from q where the simulation's pinocchio model has it (the flange, panda_link8,
    is the EE the controllers command), in light (collision meshes) and full mode; the gripper is
    not drawn (the lab's end effector is the plate)."""
    model = PandaModel()
    robot = PandaUrdf(server, light)
    assert robot.urdf.actuated_joint_names == [f"panda_joint{i}" for i in range(1, 8)]
    assert not [link for link in robot.urdf.link_map if link.startswith(NOT_SHOWN)]
    rng = np.random.default_rng(7)
    for _ in range(3):
        q = rng.uniform(model.q_min, model.q_max)
        robot.place(q)
        np.testing.assert_allclose(
            robot.transform_link_to_base("panda_link8"), model.transform_ee_to_base(q), atol=1e-9
        )
        pin.framesForwardKinematics(model.model, model.data, q)
        for link in ("panda_link3", "panda_link5"):
            placement = model.data.oMf[model.model.getFrameId(link)].homogeneous
            np.testing.assert_allclose(robot.transform_link_to_base(link), placement, atol=1e-9)


def test_wxyz_is_the_rotations_quaternion_scalar_first():
    half = np.pi / 4  # 90 degrees about z: (cos 45, 0, 0, sin 45)
    rotation = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    np.testing.assert_allclose(wxyz(rotation), [np.cos(half), 0.0, 0.0, np.sin(half)], atol=1e-12)
