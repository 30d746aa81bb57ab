"""The wall-following grader's trials and report (docs/mobile-lab.md, "Grading"): what a seed draws
for each trial (the arena's obstacle, its shape, size and place; the start pose; the wheels' and
the scan's noise: sim/mobile/world.py `seeded_config`), one report item per trial judged by the
world's monitor (sim/mobile/monitor.py), and the pass mark. Running a trial needs a live lab the
student's program talks to (a server, rosbridge): that is app/grading/wall_trial.py's, handed to the
job runner (sim/procedures/runner.py) as each trial's job.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from sim.mobile.world import MobileConfig, seeded_config

from app.grading.report import PUBLIC_SEED, Item, Report

KIND = "wall following"
SECTION = "trials"
TRIALS = 3  # per file, by default
PASS_MARK = 60.0  # % of the trials: two of three
LOST = "not graded: "  # an item whose worker died on every try


def new_wall_report(subject: str, seed: int) -> Report:
    return Report(subject, KIND, seed, marks={"": PASS_MARK})


def trial_seed(seed: int, index: int) -> int:
    """Trial `index`'s own seed (where it runs never changes what it draws)."""
    return seed * 1000 + index


def trial_configs(seed: int, trials: int = TRIALS) -> list[MobileConfig]:
    return [seeded_config(trial_seed(seed, i)) for i in range(trials)]


def describe(config: MobileConfig) -> str:
    """A trial's world in a report's words: its obstacle and the robot's start pose."""
    x, y, yaw = config.start_pose
    return f"{config.arena.obstacles[0].describe()}; start ({x:.2f}, {y:.2f}) m facing {math.degrees(yaw):.0f} deg"


@dataclass(frozen=True)
class TrialOutcome:
    """What a trial's run found: the monitor's verdict, or why the program never drove."""

    passed: bool
    verdict: str


def trial_name(index: int, config: MobileConfig, seed: int) -> str:
    """A trial's name in its report: its world described under the public seed (every student can
    draw it at home); under a course's private seed its number alone (what it drew stays the course's)."""
    if seed != PUBLIC_SEED:
        return f"trial {index + 1} (its arena drawn from the private seed)"
    return f"trial {index + 1}: {describe(config)}"


def trial_item(index: int, config: MobileConfig, seed: int, outcome: TrialOutcome) -> Item:
    return Item(SECTION, trial_name(index, config, seed), 1.0 if outcome.passed else 0.0, 1.0, outcome.verdict)


def lost_item(index: int, config: MobileConfig, seed: int, why: str) -> Item:
    return Item(SECTION, trial_name(index, config, seed), 0.0, 1.0, f"{LOST}{why}")
