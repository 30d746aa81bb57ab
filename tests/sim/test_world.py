"""The assembled lab: sensor sign and noise, move to start, human, controller failures, end to end."""

import numpy as np
import pytest

from sim.controllers.interface import LiftingParams
from sim.monitor import TrialRules
from sim.person.human import HandPath, PickAndPlace
from sim.person.participants import PARTICIPANTS
from sim.physics.sensor import SensorParams, WrenchSensor
from sim.procedures.experiment import plan, run_experiment
from sim.procedures.trial import Setup, Trial
from sim.robot.panda import READY_Q, SIDE_Q
from sim.signals import minimum_jerk
from sim.world import World, WorldConfig


def quiet_world(**config) -> World:
    return World(WorldConfig(sensor=SensorParams(force_noise_std=0.0, moment_noise_std=0.0), **config))


def test_start_pose_faces_the_person():
    world = World()
    transform = world.arm.transform_ee_to_base
    assert transform[:3, 2] == pytest.approx([0, 1, 0], abs=1e-3)  # plate normal = base +y
    assert transform[:3, 3] == pytest.approx([0.60, 0.15, 0.35], abs=2e-3)
    # the box waits a few cm in front of the plate, the palm on its far face
    gap = world.box.position[1] - 0.1 - (transform[1, 3] + world.config.plate.offset)
    assert gap == pytest.approx(world.config.start_gap, abs=1e-6)


def test_pressing_gives_positive_f_n_and_the_robot_stops_in_the_band():
    """Start at 10 N: the robot approaches, F_ext f_n rises (> 0 when pressing, franka's sign) and
    settles inside [10, 15] while the person still holds the box grasped."""
    world = quiet_world()
    world.start_lifting(10.0)
    before = world.arm.transform_ee_to_base[:3, 3].copy()
    world.run(1.5)
    wrench = world.wrench_ee_true
    assert 10.0 - 0.5 <= wrench[2] <= 15.0 + 0.5
    assert world.plate_state.normal_force == pytest.approx(wrench[2], rel=1e-3)  # face ~ parallel to the plate
    moved = world.arm.transform_ee_to_base[:3, 3] - before
    assert moved[1] == pytest.approx(world.config.start_gap, abs=0.01)  # toward the box along +y
    assert world.error is None


def test_sensor_noise_and_filter():
    rng = np.random.default_rng(0)
    true = np.array([1.0, 2.0, 3.0, 0.1, 0.2, 0.3])
    raw = WrenchSensor(SensorParams(0.5, 0.05, 0.0), rng)
    samples = np.array([raw.measure(true, 1e-3) for _ in range(20000)])
    assert samples.mean(axis=0) == pytest.approx(true, abs=0.02)
    assert samples.std(axis=0) == pytest.approx([0.5] * 3 + [0.05] * 3, rel=0.05)
    filtered = WrenchSensor(SensorParams(0.5, 0.05, 10.0), rng)
    samples = np.array([filtered.measure(true, 1e-3) for _ in range(20000)])[1000:]
    # first-order low-pass, white noise: std = sigma sqrt(a / (2 - a)), a = dt / (tau + dt)
    a = 1e-3 / (1 / (2 * np.pi * 10) + 1e-3)
    assert samples[:, 0].std() == pytest.approx(0.5 * np.sqrt(a / (2 - a)), rel=0.15)


def test_move_to_start_drives_there_smoothly():
    world = quiet_world(start_q=tuple(READY_Q))
    world.config = WorldConfig(start_q=tuple(SIDE_Q))
    motion = world.move_to_start()
    steps = 0
    while world.motion is not None:
        world.step()
        steps += 1
    assert world.error is None
    assert world.arm.q == pytest.approx(SIDE_Q, abs=1e-3)
    assert steps == pytest.approx(motion.duration / 1e-3, abs=2)


def test_move_to_start_while_jogging_brakes_first_and_gets_there_without_a_reflex():
    world = quiet_world()
    world.start_jog(np.array([0.1, 0.0, 0.0, 0.0, 0.0, 0.0]))  # teleop 'w': +x at 0.1 m/s for 0.5 s
    world.run(0.2)  # mid-jog: the joints move
    moving = world.arm.qdot.copy()
    assert np.max(np.abs(moving)) > 0.05
    motion = world.move_to_start()
    braking = np.max(np.abs(moving)) / 2.0  # s at the brake's 2 rad/s^2
    while world.motion is not None:
        world.step()
        assert world.error is None, world.error
    assert world.jog is None  # the jog is cancelled: it does not resume at the start pose
    assert world.arm.q == pytest.approx(SIDE_Q, abs=1e-3)
    assert motion.duration == pytest.approx(braking + motion.move.duration, abs=0.01)
    world.run(0.5)
    assert world.arm.q == pytest.approx(SIDE_Q, abs=1e-3)


def test_minimum_jerk_path():
    assert [minimum_jerk(t) for t in (0.0, 0.5, 1.0)] == pytest.approx([0.0, 0.5, 1.0])
    path = HandPath(PickAndPlace(), peak_speed=0.1)
    # lift 0.2 m at peak 0.1 m/s takes T = 1.875 * 0.2 / 0.1 = 3.75 s
    assert path.segments[0][1] == pytest.approx(3.75)
    assert path.offset(3.75) == pytest.approx([0, 0, 0.2])
    assert path.offset(path.duration) == pytest.approx([-0.3, 0.0, 0.0])
    assert path.duration == pytest.approx(3.75 * 2 + 1.875 * 0.3 / 0.1 + 1.0)


def test_palm_follows_a_target_set_directly():
    world = quiet_world()
    human = world.human
    target = human.position + np.array([0.0, 0.0, 0.05])
    human.set_target(target)
    for _ in range(1500):
        human.step(1e-3, 0.0, 0.0, 0.0, None, np.eye(3))
    assert human.phase == "manual"
    assert human.position == pytest.approx(target, abs=2e-3)
    with pytest.raises(ValueError):  # noqa: PT011 - any ValueError is the refusal under test
        human.set_target([0.0, float("nan"), 0.0])


def test_controller_exception_is_an_error_state_not_a_crash():
    class Broken:
        def reset(self):
            pass

        def step(self, wrench, transform, params, dt):
            raise RuntimeError("boom")

    world = World(controller=Broken())
    world.run(0.01)
    assert world.error is not None
    assert "boom" in world.error
    assert world.arm.qdot == pytest.approx(np.zeros(7))
    world.run(0.01)  # the loop goes on
    assert world.time == pytest.approx(0.02)


def test_nan_twist_from_a_controller_is_refused():
    class NaNController:
        def reset(self):
            pass

        def step(self, wrench, transform, params, dt):
            return np.full(6, np.nan)

    world = World(controller=NaNController())
    world.run(0.01)
    assert "invalid command" in world.error
    assert np.all(np.isfinite(world.arm.q))


def test_calm_trial_succeeds_with_lifting_at_10_newton():
    trial = Trial(PARTICIPANTS["calm"], seed=11)
    result = trial.run()
    assert result.success, result.reason
    assert trial.world.human.phase == "done"
    # the box went where the person carried it: up, over and down again (0.30 m along -x)
    box = trial.world.box.position
    assert box[0] == pytest.approx(0.30, abs=0.02)
    assert result.slip < 0.02
    assert result.f_n_min > 9.0
    assert result.f_n_max < 25.0


def test_same_trial_fails_when_the_controller_is_stopped():
    """Lifting stopped once the person has let go of the grasp: the robot no longer follows, the
    person lifts, the plate holds the box back and the box is dropped (slip or lost contact)."""
    trial = Trial(PARTICIPANTS["calm"], seed=11)
    while trial.world.human.phase != "settling":
        assert trial.step()
    trial.world.stop_lifting()
    result = trial.run()
    assert not result.success
    assert result.reason.startswith("dropped")
    assert np.linalg.norm(trial.world.arm.twist_base) < 1e-6  # the robot stood still


def test_robot_never_started_means_no_grip():
    rules = TrialRules(approach_limit=2.0)
    trial = Trial(PARTICIPANTS["calm"], seed=1, rules=rules)
    trial.world.stop_lifting()
    result = trial.run()
    assert not result.success
    assert result.reason.startswith("no grip")


SHORT = Setup(
    params=LiftingParams(alpha=0.8)
)  # the short trial: at the wider margin alpha 0.8 the hasty participant's box drops at ~3 s


def test_experiment_is_deterministic_per_seed():
    a = run_experiment(1, "hasty", seed=5, setup=SHORT)
    b = run_experiment(1, "hasty", seed=5, setup=SHORT)
    assert [r.as_dict() for r in a] == [r.as_dict() for r in b]
    assert plan(9)[0][3] != plan(9, seed=1)[0][3]
    # in parallel processes: the same results, in plan order
    serial = run_experiment(2, "hasty", seed=6, setup=SHORT)
    parallel = run_experiment(2, "hasty", seed=6, jobs=2, setup=SHORT)
    assert [r.as_dict() for r in parallel] == [r.as_dict() for r in serial]
    # nine trials = three participants x three tries
    assert [(p.name, attempt) for _, p, attempt, _ in plan(9)] == [
        (name, k) for name in ("calm", "average", "hasty") for k in (1, 2, 3)
    ]


def _sim_ends():
    """The ends of every accepted `sim` parameter's range: box mass x contact stiffness (what decides
    the integration's stability), the sensor at its noisiest and unfiltered; and everything at its low end."""
    from itertools import product

    from app.lab.params import LAB_PARAMETERS

    ranges = {p.name: (p, p.range) for p in LAB_PARAMETERS if p.node == "sim" and p.offline is not None}
    noisy = {name: high for name, (_, (low, high)) in ranges.items() if name not in ("box_mass", "contact_stiffness")}
    cases = [
        {"box_mass": m, "contact_stiffness": k, **noisy}
        for m, k in product(ranges["box_mass"][1], ranges["contact_stiffness"][1])
    ]
    cases.append({name: low for name, (_, (low, high)) in ranges.items()})
    return [(case, [(ranges[name][0], value) for name, value in case.items()]) for case in cases]


@pytest.mark.parametrize(
    ("case", "overrides"),
    _sim_ends(),
    ids=lambda c: "-".join(f"{v:g}" for v in c.values()) if isinstance(c, dict) else "",
)
def test_every_accepted_sim_parameter_value_is_stable(case, overrides):
    """Grip and release at the ends of the ranges: the box stays where the hands hold it (an
    unstable integration blows it away within a few steps: a 0.05 kg box without substeps did
    at the 12th)."""
    from sim.procedures.trial import make_trial

    from app.lab.overrides import setup_of

    index, person, attempt, seed = plan(1, "calm", 0)[0]
    trial = make_trial(index, person, attempt, seed, setup=setup_of(overrides))
    box, start = trial.world.box, trial.world.box.position.copy()
    for _ in range(1000):  # the robot presses the box into the band, the person lets go
        if not trial.step():
            break
        assert np.all(np.isfinite(box.position))
        assert np.linalg.norm(box.velocity) < 0.5
    assert np.linalg.norm(box.position - start) < 0.1


def test_reset_gives_a_sane_world_at_every_box_mass():
    world = World()
    for mass in (0.05, 5.0):
        world.set_box(mass=mass)
        world.reset()
        start = world.box.position.copy()
        world.run(0.3)
        assert np.all(np.isfinite(world.box.position))
        assert np.linalg.norm(world.box.position - start) < 0.02


def test_the_live_world_judges_its_scripted_participant_like_the_experiment():
    """Lifting started while the person grasps the box starts a trial; the world applies the
    experiment's rule after every step: the same figures as the headless trial with that seed."""
    world = World()  # the hasty participant: the shortest trial that succeeds (~10 s simulated)
    world.reset(PARTICIPANTS["hasty"].varied(np.random.default_rng(11)), seed=11)
    assert world.snapshot().trial.state == "none"
    world.start_lifting(10.0)
    world.step()
    assert world.snapshot().trial.state == "running"
    assert world.snapshot().trial.participant == "hasty"
    while world.trial.state == "running":
        world.step()
    live = world.snapshot().trial
    headless = Trial(PARTICIPANTS["hasty"], seed=11).run()
    assert live.state == "succeeded"
    assert live.reason == ""
    assert (live.duration, live.slip, live.f_n_min, live.f_n_max, live.max_friction_ratio) == pytest.approx(
        (headless.duration, headless.slip, headless.f_n_min, headless.f_n_max, headless.max_friction_ratio), abs=1e-9
    )
    world.reset()
    assert world.snapshot().trial.state == "none"


def test_a_live_trial_taken_over_by_the_gizmo_is_abandoned_and_stopping_drops_the_box():
    world = World()
    world.run(0.3)  # waiting before lifting starts is not counted
    world.start_lifting(10.0)
    world.run(0.1)
    assert world.snapshot().trial.duration == pytest.approx(0.1)
    world.human.set_target(world.human.position)
    world.step()
    assert (world.trial.state, world.trial.reason) == (
        "abandoned",
        "abandoned: the palm was taken over (no scripted result)",
    )
    world.reset()
    world.start_lifting(10.0)
    while world.human.phase != "settling":
        world.step()
    world.stop_lifting()  # the robot no longer follows: the person lifts, the box is dropped
    while world.trial.state == "running":
        world.step()
    assert world.trial.state == "failed"
    assert world.trial.reason.startswith("dropped")
