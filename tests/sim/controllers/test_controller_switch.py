"""A controller switch while lifting (sp -> patch, patch -> sp) is bumpless: the new controller
starts from the running command, so the command never jumps and no reflex trips."""

import numpy as np
import pytest

from sim.controllers.builtin import builtin
from sim.controllers.interface import LiftingParams
from sim.person.participants import PARTICIPANTS
from sim.procedures.trial import Trial


def carrying_fast(controller: str) -> Trial:
    """A trial carrying with the built-in `controller`, the robot following fast enough (> 2 cm/s)
    that a restart from rest would jump the command."""
    trial = Trial(PARTICIPANTS["average"], seed=3)
    world = trial.world
    world.set_controller(builtin(controller))
    world.start_lifting(10.0)
    while not (world.human.phase == "carrying" and np.linalg.norm(world.twist_command[:3]) > 0.02):
        assert trial.step()
        assert world.time < 30.0
    return trial


@pytest.mark.parametrize(("before", "after"), [("sp", "patch"), ("patch", "sp")])
def test_switching_the_controller_while_carrying_keeps_the_command_continuous(before, after):
    trial = carrying_fast(before)
    world = trial.world
    commands = [world.twist_command.copy()]
    world.set_controller(builtin(after))
    for _ in range(500):
        trial.step()
        commands.append(world.twist_command.copy())
    assert world.error is None
    limits = LiftingParams()
    steps = np.diff(np.array(commands), axis=0)
    dt = world.config.dt
    # step 6's rate limit holds across the switch: |dv| <= a_max dt, |dw| <= dw_max dt
    assert np.linalg.norm(steps[:, :3], axis=1).max() <= limits.a_max * dt * (1 + 1e-9)
    assert np.linalg.norm(steps[:, 3:], axis=1).max() <= limits.dw_max * dt * (1 + 1e-9)
    assert type(world.controller).__name__.lower().startswith(after)


def test_a_nodes_first_command_while_the_lab_lifts_takes_over_without_a_jump():
    """A node whose start service started the lab's lifting (the built-in SP moves the robot) and
    whose first twist comes only later: the external command takes over from the running command,
    so the robot follows the node's twist within the rate limit and no reflex trips (from rest the
    step to the node's command would be a jump)."""
    from sim.controllers.external import ExternalCommand

    trial = carrying_fast("sp")
    world = trial.world
    running = world.twist_command.copy()
    node = ExternalCommand()
    world.set_controller(node)
    node.command(running)  # the node asks for what the robot does now
    commands = [running]
    for _ in range(50):
        trial.step()
        commands.append(world.twist_command.copy())
    assert world.error is None
    limits = LiftingParams()
    steps = np.diff(np.array(commands), axis=0)
    assert np.linalg.norm(steps[:, :3], axis=1).max() <= limits.a_max * world.config.dt * (1 + 1e-9)
