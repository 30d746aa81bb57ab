"""Teleop jog (the seed's keytwist): a key becomes a short EE twist in the base frame, ramped up
and down within an acceleration limit so that it never trips the robot's reflexes.

    w / s: +/- linear_speed along base x      a / d: +/- angular_speed about base z     q: stop
"""

from __future__ import annotations

import numpy as np

KEYS = ("w", "s", "a", "d", "q")


def key_twist(key: str, linear_speed: float, angular_speed: float) -> np.ndarray:
    """The twist [v, w] (m/s, rad/s, base frame) a key asks for."""
    twist = np.zeros(6)
    if key == "w":
        twist[0] = linear_speed
    elif key == "s":
        twist[0] = -linear_speed
    elif key == "a":
        twist[5] = angular_speed
    elif key == "d":
        twist[5] = -angular_speed
    elif key != "q":
        raise ValueError(f"unknown key {key!r}: use one of {', '.join(KEYS)}")
    return twist


class Jog:
    """Hold `target` for `duration` s, reaching it and returning to rest at a_max / dw_max."""

    def __init__(self, target: np.ndarray, duration: float = 0.5, a_max: float = 0.5, dw_max: float = 1.0) -> None:
        self.target = np.asarray(target, float)
        self.remaining = duration
        self.limits = np.array([a_max] * 3 + [dw_max] * 3)
        self.twist = np.zeros(6)

    def start_from(self, twist: np.ndarray) -> Jog:
        self.twist = np.asarray(twist, float).copy()
        return self

    @property
    def done(self) -> bool:
        return self.remaining <= 0.0 and not np.any(self.twist)

    def step(self, dt: float) -> np.ndarray:
        self.remaining -= dt
        goal = self.target if self.remaining > 0.0 else np.zeros(6)
        self.twist = self.twist + np.clip(goal - self.twist, -self.limits * dt, self.limits * dt)
        return self.twist.copy()
