"""The flat contact plate mounted on the Panda's flange (its own module: a controller needs its
size and offset, not the robot model)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Plate:
    """The flat contact plate on the flange (m)."""

    width: float = 0.10  # along flange x
    height: float = 0.10  # along flange y
    offset: float = 0.02  # centre along flange +z
