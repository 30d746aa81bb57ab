"""app/grading/wall.py: a trial's item names its arena under the public seed (every student can
draw it at home) and nothing of it under a course's private seed, for a judged trial and a lost one alike."""

from app.grading.report import PUBLIC_SEED
from app.grading.wall import TrialOutcome, describe, lost_item, trial_configs, trial_item


def test_the_public_seeds_arena_is_described_and_a_private_seeds_is_not():
    private = 4711
    (public_config,) = trial_configs(PUBLIC_SEED, 1)
    (private_config,) = trial_configs(private, 1)
    outcome = TrialOutcome(False, "collision: at 3.0 s the robot touched the obstacle")
    assert trial_item(0, public_config, PUBLIC_SEED, outcome).name == f"trial 1: {describe(public_config)}"
    for item in (trial_item(0, private_config, private, outcome), lost_item(0, private_config, private, "died")):
        assert item.name == "trial 1 (its arena drawn from the private seed)"
        shape = private_config.arena.obstacles[0]
        assert f"{shape.center_xy[0]:.2f}" not in item.name + item.detail
        assert describe(private_config) not in item.name + item.detail
