"""What the views draw with (app/view/scene.py): the friction cone's shape, the Panda where its URDF
puts each link (yourdfpy, the URDF view's reader, as an independent forward kinematics), its
meshes' cache, rotations as viser's quaternions."""

import numpy as np
import pytest
import viser

from sim.robot.assets import panda_urdf
from sim.robot.panda import PandaModel

from app.view.scene import NOT_SHOWN, RobotMeshes, cone_mesh, glb_of, wxyz


def test_friction_cone_opening_is_mu():
    vertices, faces = cone_mesh(0.5, height=0.1)
    radius = np.linalg.norm(vertices[1:, :2], axis=1)
    assert radius == pytest.approx(0.05, rel=1e-6)  # tan(half angle) = r / h = mu
    assert np.all(vertices[1:, 2] == pytest.approx(0.1))
    assert faces.shape == (24, 3)


def test_converted_meshes_are_cached(tmp_path, monkeypatch):
    """The .dae -> GLB conversion (seconds for the full Panda) happens once; later starts read the cache."""
    from pathlib import Path

    import pinocchio as pin

    from sim.robot.assets import panda_urdf, robot_data_share
    from sim.robot.panda import PandaModel

    monkeypatch.setenv("HRI_LAB_CACHE", str(tmp_path))
    geometry = pin.buildGeomFromUrdf(
        PandaModel().model, str(panda_urdf()), pin.GeometryType.VISUAL, package_dirs=[str(robot_data_share())]
    )
    mesh = next(o for o in geometry.geometryObjects if o.meshPath.endswith(".dae"))
    first = glb_of(Path(mesh.meshPath), tuple(mesh.meshScale))
    assert first[:4] == b"glTF"
    (cached,) = tmp_path.glob("*.glb")
    assert cached.read_bytes() == first
    cached.write_bytes(b"glTF from the cache")
    assert glb_of(Path(mesh.meshPath), tuple(mesh.meshScale)) == b"glTF from the cache"
    assert glb_of(Path(mesh.meshPath), (2.0, 2.0, 2.0)) != b"glTF from the cache"  # another scale, another entry


def test_the_panda_is_drawn_where_its_urdf_puts_each_link():
    """Each mesh's frame (what the browser is sent: position and wxyz) at q is where yourdfpy, read
    from the same URDF, puts the mesh's link; the gripper is not drawn (the end effector is the plate)."""
    import yourdfpy

    urdf = yourdfpy.URDF.load(str(panda_urdf()), build_scene_graph=True, load_meshes=False)
    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        robot = RobotMeshes(server, light=True)
        links = {
            index: robot.model.model.frames[robot.geometry.geometryObjects[index].parentFrame].name
            for index, _ in robot.frames
        }
        assert sorted(links.values()) == [f"panda_link{i}" for i in range(8)]  # every arm link, no gripper
        assert not [name for name in links.values() if name.startswith(NOT_SHOWN)]
        rng = np.random.default_rng(7)
        model = PandaModel()
        for _ in range(3):
            q = rng.uniform(model.q_min, model.q_max)
            robot.place(q)
            urdf.update_cfg(np.concatenate((q, np.zeros(len(urdf.actuated_joint_names) - len(q)))))  # fingers shut
            for index, frame in robot.frames:
                expected = urdf.get_transform(links[index])
                np.testing.assert_allclose(frame.position, expected[:3, 3], atol=1e-6)
                np.testing.assert_allclose(frame.wxyz, wxyz(expected[:3, :3]), atol=1e-6)
    finally:
        server.stop()


def test_wxyz_is_the_rotations_quaternion_scalar_first():
    half = np.pi / 4  # 90 degrees about z: (cos 45, 0, 0, sin 45)
    rotation = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    np.testing.assert_allclose(wxyz(rotation), [np.cos(half), 0.0, 0.0, np.sin(half)], atol=1e-12)
