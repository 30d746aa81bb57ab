"""The rotation exp/log the kernels compile (sim/spatial.py's exp3, log3, compiled in
sim/person/human.py) against pinocchio's exp3/log3, and the compiled orthonormalize."""

import numpy as np
import pinocchio as pin

from sim.person.human import exp3, log3
from sim.physics.box import orthonormalize


def test_compiled_exp_and_log_equal_pinocchios_at_random_rotations():
    rng = np.random.default_rng(3)
    for scale in (1e-9, 1e-5, 1e-3, 0.1, 1.0, 3.0, np.pi - 1e-3, np.pi - 1e-7):
        for _ in range(200):
            axis = rng.normal(size=3)
            w = axis / np.linalg.norm(axis) * scale * (rng.uniform(0.5, 1.0) if scale < 3 else 1.0)
            np.testing.assert_allclose(exp3(w), pin.exp3(w), rtol=0, atol=1e-12)
            r = pin.exp3(w)
            np.testing.assert_allclose(log3(r), pin.log3(r), rtol=0, atol=1e-7 if scale > 3 else 1e-12)


def test_compiled_orthonormalize_removes_drift():
    rng = np.random.default_rng(4)
    r = pin.exp3(rng.normal(size=3)) + rng.normal(size=(3, 3)) * 1e-6
    fixed = orthonormalize(r)
    np.testing.assert_allclose(fixed @ fixed.T, np.eye(3), atol=1e-12)
    assert np.linalg.det(fixed) > 0
    assert np.abs(fixed - r).max() < 1e-5
