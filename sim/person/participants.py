"""The participants of the experiment (lab Table 1, plus two harder ones for comparing
controllers): how fast each moves, how hard each squeezes, how much each trembles.
The virtual human that plays them is sim/person/human.py."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np


@dataclass(frozen=True)
class Participant:
    """A person of the experiment (lab Table 1)."""

    name: str
    peak_speed: float  # m/s, peak speed of each minimum-jerk segment
    squeeze_force: float  # N, palm force the person keeps
    tremor_amplitude: float  # m, per axis
    tremor_frequency: float  # Hz (physiological tremor is 8-12 Hz)
    tilt: float = 0.0  # rad the person tilts the box (about the carry direction) while carrying it

    def varied(self, rng: np.random.Generator) -> Participant:
        """The same person on another try: +-10 % speed, +-1 N squeeze."""
        return replace(
            self,
            peak_speed=self.peak_speed * rng.uniform(0.9, 1.1),
            squeeze_force=self.squeeze_force + rng.uniform(-1.0, 1.0),
        )


PARTICIPANTS: dict[str, Participant] = {
    p.name: p
    for p in (
        Participant("calm", peak_speed=0.08, squeeze_force=14.0, tremor_amplitude=0.0002, tremor_frequency=8.0),
        Participant("average", peak_speed=0.12, squeeze_force=13.0, tremor_amplitude=0.0005, tremor_frequency=9.0),
        Participant("hasty", peak_speed=0.16, squeeze_force=12.0, tremor_amplitude=0.001, tremor_frequency=10.0),
        # harder participants for comparing controllers (not in the handout's Table 1)
        Participant("brisk", peak_speed=0.14, squeeze_force=14.0, tremor_amplitude=0.0005, tremor_frequency=9.0),
        Participant(
            "tilting",
            peak_speed=0.08,
            squeeze_force=14.0,
            tremor_amplitude=0.0002,
            tremor_frequency=8.0,
            tilt=math.radians(15.0),
        ),
    )
}
TABLE_1 = ("calm", "average", "hasty")  # the handout's three participants
