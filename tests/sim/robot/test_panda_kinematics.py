"""The compiled flange pose and Jacobian (sim/robot/panda_kinematics.py) against pinocchio, the
robot model of record, at many random configurations (inside and beyond the joint limits)."""

import numpy as np
import pinocchio as pin

from sim.robot.panda import PandaModel
from sim.robot.panda_kinematics import chain_kinematics


def compiled(panda, q):
    c = panda.chain
    transform, jacobian = np.zeros((4, 4)), np.zeros((6, 7))
    chain_kinematics(
        q, c.rotations, c.translations, c.axes, c.flange_rotation, c.flange_translation, transform, jacobian
    )
    return transform, jacobian


def test_compiled_kinematics_equal_pinocchios_at_random_configurations():
    panda = PandaModel()
    rng = np.random.default_rng(7)
    span = panda.q_max - panda.q_min
    for _ in range(2000):
        q = rng.uniform(panda.q_min - 0.5 * span, panda.q_max + 0.5 * span)
        transform, jacobian = compiled(panda, q)
        pin.framesForwardKinematics(panda.model, panda.data, q)
        expected = panda.data.oMf[panda.flange_id].homogeneous
        np.testing.assert_allclose(transform, expected, rtol=0, atol=1e-12)
        expected_jacobian = pin.computeFrameJacobian(
            panda.model, panda.data, q, panda.flange_id, pin.LOCAL_WORLD_ALIGNED
        )
        np.testing.assert_allclose(jacobian, expected_jacobian, rtol=0, atol=1e-12)


def test_the_chain_is_read_from_pinocchios_model():
    """A change in pinocchio's model (a longer link 4) changes the compiled kinematics the same way."""
    panda = PandaModel()
    panda.model.jointPlacements[4] = pin.SE3(
        panda.model.jointPlacements[4].rotation, panda.model.jointPlacements[4].translation + np.array([0.05, 0.0, 0.0])
    )
    panda.data = panda.model.createData()
    from sim.robot.panda_kinematics import chain_arrays

    panda.chain = chain_arrays(panda.model, panda.flange_id)
    q = np.array([0.1, -0.3, 0.2, -2.0, 0.1, 1.5, 0.7])
    transform, _jacobian = compiled(panda, q)
    default = compiled(PandaModel(), q)[0]
    pin.framesForwardKinematics(panda.model, panda.data, q)
    np.testing.assert_allclose(transform, panda.data.oMf[panda.flange_id].homogeneous, atol=1e-12)
    assert np.linalg.norm(transform[:3, 3] - default[:3, 3]) > 0.01
