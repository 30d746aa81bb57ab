"""The external-command controller (a node's Twist): franka's command watchdog in simulation time,
limit_rate smoothing, and the robot's reflexes still in force."""

import numpy as np

from sim.controllers.external import ExternalCommand
from sim.world import World

from app.lab import commands as cmd


def test_a_command_selects_the_external_controller_and_is_followed_smoothly():
    world = World()
    cmd.external_twist(world, np.array([0.0, 0.0, 0.05, 0.0, 0.0, 0.0]))
    assert isinstance(world.controller, ExternalCommand)
    world.step()
    # limit_rate: one period moves the command by at most a_max dt = 1 m/s^2 * 1 ms = 1 mm/s
    assert world.twist_command[2] == np.float64(0.001)
    for _ in range(60):  # renewed every 10 ms, 50 ms to reach it
        if world.time * 1000 % 10 < 1:
            cmd.external_twist(world, np.array([0.0, 0.0, 0.05, 0.0, 0.0, 0.0]))
        world.step()
    assert abs(world.twist_command[2] - 0.05) < 1e-12
    assert world.error is None


def test_a_command_not_renewed_within_the_period_stops_the_robot():
    world = World()
    cmd.external_twist(world, np.zeros(6))
    for _ in range(100):  # 100 ms: still valid
        world.step()
    assert world.error is None
    world.step()  # 101 ms
    assert world.error.startswith(
        "communication constraints violation: no command on /cartesian_velocity_controller/command"
    )
    world.recover()  # error recovery: waits for a new first command
    world.run(0.5)
    assert world.error is None


def test_the_period_is_a_parameter_and_limits_still_trip_reflexes():
    world = World()
    cmd.set_command_period(world, 0.5)
    cmd.external_twist(world, np.array([2.0, 0.0, 0.0, 0.0, 0.0, 0.0]))  # beyond the 1.7 m/s limit
    assert world.controller.period == 0.5
    for _ in range(1800):  # ramps at 1 m/s^2 toward 2 m/s, renewed every 0.2 s
        if round(world.time * 1000) % 200 == 0:
            cmd.external_twist(world, np.array([2.0, 0.0, 0.0, 0.0, 0.0, 0.0]))
        world.step()
        if world.error:
            break
    assert world.error is not None
    assert "velocity" in world.error
    assert "communication" not in world.error


def test_a_non_finite_command_is_refused():
    controller = ExternalCommand()
    for bad in ([np.nan, 0, 0, 0, 0, 0], [0.0] * 5):
        try:
            controller.command(np.array(bad, dtype=float))
        except ValueError as exc:
            assert "6 finite numbers" in str(exc)  # noqa: PT017 - the exception's text is the subject, checked where it is caught
        else:
            raise AssertionError(f"{bad} was accepted")
