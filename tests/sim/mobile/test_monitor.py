"""The wall-following rule on hand-made paths: a circuit passes; a collision, a stall, too long
outside the band and the time limit each fail with their figures."""

import math

import pytest

from sim.mobile.monitor import WallMonitor, WallRules

RULES = WallRules()
DT = 0.005


def circle_path(monitor: WallMonitor, radius: float, surface: float, speed: float, seconds: float) -> None:
    """Round the centre (0, 0) at `radius`, `surface` m from the obstacle's surface."""
    omega = speed / radius
    for k in range(1, int(seconds / DT) + 1):
        a = omega * k * DT
        monitor.update(DT, (radius * math.cos(a), radius * math.sin(a)), surface, None)
        if monitor.state.done:
            return


def test_a_full_circuit_in_the_band_passes():
    m = WallMonitor(RULES, (0.0, 0.0), (0.8, 0.0))
    circle_path(m, 0.8, 0.4, 0.15, 60.0)
    assert m.state.passed
    assert m.state.verdict.startswith("circuit")
    assert m.state.elapsed == pytest.approx(2 * math.pi * 0.8 / 0.15, abs=0.01)
    assert "counter-clockwise" in m.state.verdict


def test_a_collision_fails_at_once_with_its_time():
    m = WallMonitor(RULES, (0.0, 0.0), (0.8, 0.0))
    for _ in range(100):
        m.update(DT, (0.8, 0.0), 0.4, None)
    m.update(DT, (0.8, 0.0), 0.09, "the obstacle")
    assert m.state.done
    assert not m.state.passed
    assert m.state.verdict == "collision: at 0.5 s the robot touched the obstacle (0.09 m from the obstacle)"


def test_standing_still_is_a_stall():
    m = WallMonitor(RULES, (0.0, 0.0), (0.8, 0.0))
    circle_path(m, 0.8, 0.4, 0.0, 30.0)
    assert not m.state.passed
    assert m.state.verdict.startswith("stall: at 10.0 s")


def test_too_long_outside_the_band_fails():
    m = WallMonitor(RULES, (0.0, 0.0), (1.5, 0.0))
    circle_path(m, 1.5, 1.1, 0.15, 60.0)
    assert not m.state.passed
    assert m.state.verdict.startswith("band: at 20.0 s")
    assert "beyond 0.70 m" in m.state.verdict


def test_the_time_limit():
    rules = WallRules(time_limit=30.0)
    m = WallMonitor(rules, (0.0, 0.0), (0.8, 0.0))
    circle_path(m, 0.8, 0.4, 0.05, 60.0)
    assert m.state.verdict.startswith("time: at 30 s the robot had gone 107 of 360 degrees")
