"""The compiled built-in laws (sim/controllers/compiled_law.py) against the Python classes of
record (SPController, PatchController): the same commands and slipping flags, step after step, at
random wrenches (in and out of contact, inside and beyond the cone, with moments), poses and
parameters, from the same state."""

import numpy as np
import pytest

from sim.controllers.compiled_law import lifting_law_step
from sim.controllers.interface import LiftingParams, lifting_vector
from sim.controllers.patch import PatchController
from sim.controllers.sp import SPController
from sim.spatial import rotation_exp


def random_params(rng) -> LiftingParams:
    return LiftingParams(
        running=bool(rng.random() < 0.85),
        f_n_min=rng.uniform(0.0, 15.0),
        f_n_band=rng.uniform(1.0, 8.0),
        mu=rng.uniform(0.2, 1.0),
        alpha=rng.uniform(0.2, 0.95),
        k_n=rng.uniform(0.001, 0.02),
        k_t=rng.uniform(0.01, 0.3),
        k_w=rng.uniform(0.2, 3.0),
        moment_deadband=rng.uniform(0.0, 0.3),
        f_contact=rng.uniform(0.2, 2.0),
        v_max=rng.uniform(0.05, 0.6),
        w_max=rng.uniform(0.2, 1.5),
        a_max=rng.uniform(0.2, 3.0),
        dw_max=rng.uniform(0.5, 4.0),
        filter_hz=float(rng.choice([0.0, 5.0, 10.0, 30.0])),
        plate_offset=rng.uniform(0.0, 0.05),
    )


@pytest.mark.parametrize("make", [SPController, PatchController, lambda: PatchController(kern_scale=1.7)])
def test_the_compiled_law_commands_what_the_python_class_commands(make):
    rng = np.random.default_rng(11)
    for _ in range(40):
        python, compiled = make(), make()
        params = random_params(rng)
        rotation = rotation_exp(rng.normal(size=3))
        transform = np.eye(4)
        transform[:3, :3] = rotation
        base = np.array([*rng.normal(0, 3, 2), rng.uniform(-2, 20), *rng.normal(0, 0.3, 3)])
        for _ in range(60):
            wrench = base + rng.normal(size=6) * [2, 2, 2, 0.2, 0.2, 0.2]
            expected = python.step(wrench.copy(), transform.copy(), params, 1e-3)
            out = np.empty(6)
            lifting_law_step(
                compiled.law(),
                compiled.state,
                lifting_vector(params),
                compiled.constants(),
                wrench,
                rotation.copy(),
                1e-3,
                out,
            )
            np.testing.assert_allclose(out, expected, rtol=0, atol=1e-12)
            assert compiled.slipping == python.slipping
            np.testing.assert_allclose(compiled.state, python.state, rtol=0, atol=1e-12)
        if rng.random() < 0.5:
            params.running = not params.running


def test_a_subclass_with_its_own_twist_ee_or_step_runs_in_python():
    class Lazy(SPController):
        def twist_ee(self, wrench_ee, params):
            return np.zeros(6)

    class Still(PatchController):
        def step(self, wrench_ee, transform_ee_to_base, params, dt):
            return np.zeros(6)

    class Same(PatchController):
        pass

    assert SPController().law() is not None
    assert PatchController().law() is not None
    assert Same().law() is not None
    assert Lazy().law() is None
    assert Still().law() is None
