"""What the views draw with (app/view/scene.py): the friction cone's shape, the Panda's meshes."""

import numpy as np
import pytest

from app.view.scene import cone_mesh, glb_of


def test_friction_cone_opening_is_mu():
    vertices, faces = cone_mesh(0.5, height=0.1)
    radius = np.linalg.norm(vertices[1:, :2], axis=1)
    assert radius == pytest.approx(0.05, rel=1e-6)  # tan(half angle) = r / h = mu
    assert np.all(vertices[1:, 2] == pytest.approx(0.1)) and faces.shape == (24, 3)


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
