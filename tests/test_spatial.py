"""The compiled rotation exp/log (sim/spatial.py) against pinocchio's exp3/log3."""
import numpy as np
import pinocchio as pin

from sim.spatial import rotation_exp, rotation_log


def test_exp_and_log_equal_pinocchios_at_random_rotations():
    rng = np.random.default_rng(3)
    for scale in (1e-9, 1e-5, 1e-3, 0.1, 1.0, 3.0, np.pi - 1e-3, np.pi - 1e-7):
        for _ in range(200):
            axis = rng.normal(size=3)
            w = axis / np.linalg.norm(axis) * scale * (rng.uniform(0.5, 1.0) if scale < 3 else 1.0)
            np.testing.assert_allclose(rotation_exp(w), pin.exp3(w), rtol=0, atol=1e-12)
            r = pin.exp3(w)
            np.testing.assert_allclose(rotation_log(r), pin.log3(r), rtol=0, atol=1e-7 if scale > 3 else 1e-12)
