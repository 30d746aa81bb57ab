"""sim/person/human.py: the virtual human — the minimum-jerk hand path, letting go of the grasp once
the robot's grip (as felt) stays in the band, the squeeze regulation, tremor, the manual target,
and the grasp's spring — against numbers worked out by hand."""

import math

import numpy as np
import pytest

from sim.person.human import HandPath, HumanParams, PickAndPlace, VirtualHuman
from sim.person.participants import PARTICIPANTS, Participant
from sim.physics.contact import BoxPose

DT = 0.001
STILL = Participant("still", peak_speed=0.1, squeeze_force=14.0, tremor_amplitude=0.0, tremor_frequency=8.0)


def human(participant: Participant = STILL) -> VirtualHuman:
    return VirtualHuman(np.zeros(3), np.eye(3), participant)


def run(person: VirtualHuman, seconds: float, plate_force: float, band=(10.0, 15.0), palm_force=14.0) -> None:
    for _ in range(round(seconds / DT)):
        person.step(DT, palm_force, 0.0, plate_force, band, np.eye(3))


def test_the_path_s_segments_take_1_875_distance_over_peak_speed():
    path = HandPath(PickAndPlace(lift=0.2, carry=0.3, lower=0.2, hold=1.0), peak_speed=0.08)
    assert [t for _, t in path.segments] == pytest.approx([4.6875, 7.03125, 4.6875])
    assert path.duration == pytest.approx(17.40625)
    assert path.goal == pytest.approx([-0.3, 0.0, 0.0])
    assert path.offset(4.6875 / 2) == pytest.approx([0.0, 0.0, 0.1])  # minimum jerk is half-way at half time
    assert path.offset(4.6875 + 7.03125) == pytest.approx([-0.3, 0.0, 0.2])
    speed = (path.offset(2.34375 + 1e-4)[2] - path.offset(2.34375 - 1e-4)[2]) / 2e-4
    assert speed == pytest.approx(0.08, rel=1e-6)  # the peak speed, at the middle of a segment


def test_the_person_lets_go_once_the_felt_grip_stayed_in_the_band():
    person = human()
    run(person, 1.0, plate_force=0.0)
    assert person.phase == "grasping"
    assert person.grasp_weight == 1.0
    person = human()
    feel, dwell = HumanParams().feel_time_constant, HumanParams().grip_dwell
    let_go_at = feel * math.log(12.0 / 2.0) + dwell  # 12 N felt through 0.1 s: 10 N after 0.1 ln 6 s
    run(person, let_go_at - 0.01, plate_force=12.0)
    assert person.phase == "grasping"
    run(person, 0.02, plate_force=12.0)
    assert person.phase == "releasing"
    assert person.letting_go
    run(person, HumanParams().release_time + 0.002, plate_force=12.0)
    assert person.grasp_weight == 0.0
    assert person.holding_by_contact
    assert person.phase == "settling"
    run(person, HumanParams().settle_time, plate_force=12.0)
    assert person.phase == "carrying"


def test_a_stopped_lifting_never_lets_the_box_go():
    person = human()
    run(person, 1.0, plate_force=12.0, band=None)
    assert person.phase == "grasping"
    assert not person.letting_go


def test_the_squeeze_moves_at_k_f_times_the_missing_force():
    person = human()
    person.release()
    person.step(DT, 0.0, 0.0, 0.0, None, np.eye(3))  # weight < 1: the palm regulates
    k_f = HumanParams().k_f
    assert person.squeeze == pytest.approx(k_f * 14.0 * DT)  # 0.14 m/s, below v_squeeze_max
    assert person.position[2] == pytest.approx(person.squeeze)  # along the palm's normal, its z
    load = human()
    load.release()
    load.step(DT, 0.0, 30.0, 0.0, None, np.eye(3))  # 30 N of load in the palm: squeeze >= the load
    assert load.squeeze == pytest.approx(HumanParams().v_squeeze_max * DT)  # 0.3 m/s capped at 0.2


def test_tremor_is_in_the_palm_plane_within_its_amplitude():
    person = human(PARTICIPANTS["hasty"])
    shakes = np.array([person.tremor(t) for t in np.arange(0.0, 1.0, 0.001)])
    amplitude = PARTICIPANTS["hasty"].tremor_amplitude
    assert np.abs(shakes[:, :2]).max() == pytest.approx(amplitude, rel=0.01)
    assert np.all(shakes[:, 2] == 0.0)
    assert np.all(human().tremor(0.3) == 0.0)


def test_a_manual_target_is_followed_at_the_manual_speed_and_checked():
    person = human()
    person.set_target(np.array([1.0, 0.0, 0.0]))
    assert person.phase == "manual"
    run(person, 0.1, plate_force=0.0, band=None)
    assert person.hand == pytest.approx([HumanParams().manual_speed * 0.1, 0.0, 0.0])
    for bad in ([np.nan, 0, 0], [1.0, 2.0]):
        with pytest.raises(ValueError, match="3 finite numbers"):
            person.set_target(np.array(bad))
    with pytest.raises(ValueError, match="finite 3x3"):
        person.set_target(np.zeros(3), np.full((3, 3), np.inf))


def test_the_grasp_is_a_spring_to_where_the_box_was_grasped():
    person = human()
    box = BoxPose(np.array([0.0, 0.0, 0.1]), np.eye(3), np.zeros(3), np.zeros(3), np.full(3, 0.1))
    person.grasp(box)
    force, moment = person.hand_wrench(box, palm_force=14.0)
    assert force == pytest.approx(np.zeros(3))
    assert moment == pytest.approx(np.zeros(3))
    moved = BoxPose(np.array([0.01, 0.0, 0.1]), np.eye(3), np.zeros(3), np.zeros(3), np.full(3, 0.1))
    force, _ = person.hand_wrench(moved, palm_force=14.0)
    assert force == pytest.approx([-HumanParams().grasp_stiffness * 0.01, 0.0, 0.0])  # 50 N back
