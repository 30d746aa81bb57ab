"""sim/person/participants.py: the handout's three participants (Table 1) and the two harder ones,
and a participant varied from try to try within its bounds."""

import math

import numpy as np
import pytest

from sim.person.participants import PARTICIPANTS, TABLE_1


def test_table_1_is_the_handout_s_three_in_rising_haste():
    assert TABLE_1 == ("calm", "average", "hasty")
    speeds = [PARTICIPANTS[name].peak_speed for name in TABLE_1]
    squeezes = [PARTICIPANTS[name].squeeze_force for name in TABLE_1]
    tremors = [PARTICIPANTS[name].tremor_amplitude for name in TABLE_1]
    assert speeds == sorted(speeds)
    assert tremors == sorted(tremors)
    assert squeezes == sorted(squeezes, reverse=True)
    assert all(8.0 <= p.tremor_frequency <= 12.0 for p in PARTICIPANTS.values())  # physiological tremor


def test_only_the_tilting_participant_tilts_the_box():
    assert {name for name, p in PARTICIPANTS.items() if p.tilt} == {"tilting"}
    assert math.degrees(PARTICIPANTS["tilting"].tilt) == pytest.approx(15.0)


def test_a_try_varies_speed_by_ten_percent_and_squeeze_by_one_newton():
    calm = PARTICIPANTS["calm"]
    rng = np.random.default_rng(0)
    tries = [calm.varied(rng) for _ in range(200)]
    speeds = np.array([t.peak_speed for t in tries]) / calm.peak_speed
    squeezes = np.array([t.squeeze_force for t in tries]) - calm.squeeze_force
    assert speeds.min() >= 0.9
    assert speeds.max() <= 1.1
    assert speeds.max() - speeds.min() > 0.15
    assert squeezes.min() >= -1.0
    assert squeezes.max() <= 1.0
    assert squeezes.max() - squeezes.min() > 1.5
    assert {(t.name, t.tremor_amplitude, t.tilt) for t in tries} == {("calm", calm.tremor_amplitude, 0.0)}


def test_the_same_seed_gives_the_same_try():
    hasty = PARTICIPANTS["hasty"]
    assert hasty.varied(np.random.default_rng(7)) == hasty.varied(np.random.default_rng(7))
    assert hasty.varied(np.random.default_rng(7)) != hasty.varied(np.random.default_rng(8))
