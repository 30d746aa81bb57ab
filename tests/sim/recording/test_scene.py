"""sim/recording/scene.py: the state colours, the force arrows in the base frame (hand-computed),
Foxglove's time and arrow encoding, and a snapshot's frames and entities."""

from dataclasses import replace

import numpy as np
import pytest

from sim.recording.scene import (
    BASE_FRAME,
    COLOURS,
    FORCE_SCALE,
    LINKS,
    SceneBuilder,
    arrow_points,
    arrow_primitive,
    arrows_of,
    rgb_of,
    rotation_of,
    stamp,
    state_of,
)
from sim.world import World


@pytest.fixture(scope="module")
def world():
    return World()


def test_stamp_splits_seconds_and_nanoseconds():
    assert stamp(1.25) == {"sec": 1, "nsec": 250_000_000}
    assert stamp(0.0) == {"sec": 0, "nsec": 0}


def test_the_state_colours(world):
    s = world.snapshot()
    plate = replace(s.plate, normal_force=12.0, points_slipping=0)
    running = replace(s.lifting, running=True, f_n_min=10.0, f_n_band=5.0)
    assert state_of(replace(s, lifting=replace(s.lifting, running=False))) == "idle"
    assert state_of(replace(s, plate=plate, lifting=running)) == "inside"
    assert state_of(replace(s, plate=replace(plate, normal_force=9.0), lifting=running)) == "below"
    assert state_of(replace(s, plate=replace(plate, normal_force=16.0), lifting=running)) == "above"
    assert state_of(replace(s, plate=replace(plate, points_slipping=3), lifting=running)) == "slipping"
    assert state_of(replace(s, error="reflex", plate=plate, lifting=running)) == "error"  # error first
    assert set(COLOURS) == {"below", "inside", "above", "slipping", "error", "idle"}


def test_the_arrows_split_f_ext_at_the_plate_centre(world):
    """F_ext (3, 4, 10) N in the EE frame, the EE turned 90 deg about base z at (0.5, 0, 0.3): the
    plate normal is the EE's z (= base z), so the normal part is 10 N along base z and the
    tangential part the EE's (3, 4) turned: (-4, 3, 0) N."""
    s = world.snapshot()
    transform = np.eye(4)
    transform[:3, :3] = [[0, -1, 0], [1, 0, 0], [0, 0, 1]]
    transform[:3, 3] = [0.5, 0.0, 0.3]
    palm_force = np.array([0.0, 20.0, 0.0])
    s = replace(
        s,
        transform_ee_to_base=transform,
        wrench_ee=np.array([3.0, 4.0, 10.0, 0, 0, 0]),
        palm=replace(s.palm, force_box=palm_force),
        palm_position=np.array([0.6, 0.2, 0.3]),
    )
    arrows = arrows_of(s, plate_offset=0.02)
    centre = np.array([0.5, 0.0, 0.32])
    assert arrows["normal"] == pytest.approx(np.array([centre, centre + FORCE_SCALE * np.array([0, 0, 10.0])]))
    assert arrows["tangential"] == pytest.approx(np.array([centre, centre + FORCE_SCALE * np.array([-4.0, 3.0, 0])]))
    assert arrows["human"] == pytest.approx(np.array([[0.6, 0.2 - FORCE_SCALE * 20.0, 0.3], [0.6, 0.2, 0.3]]))


@pytest.mark.parametrize("end", [(0.1, 0.0, 0.0), (0.0, 0.0, -0.05), (0.03, -0.04, 0.12)])
def test_an_arrow_primitive_reads_back_as_its_segment(end):
    start = np.array([0.2, 0.1, 0.4])
    arrow = arrow_primitive(start, start + np.array(end), (230, 50, 50))
    assert arrow_points(arrow) == pytest.approx(np.array([start, start + np.array(end)]), abs=1e-9)
    assert arrow["head_length"] == pytest.approx(min(0.02, 0.3 * np.linalg.norm(end)))
    assert rgb_of(arrow["color"]) == (230, 50, 50)


def test_rotation_of_a_quaternion():
    half = np.sqrt(0.5)
    assert rotation_of({"x": 0.0, "y": 0.0, "z": half, "w": half}) == pytest.approx(
        np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]]), abs=1e-12
    )


def test_a_snapshot_gives_every_frame_and_entity(world):
    s = world.snapshot()
    config = world.config
    scene = SceneBuilder(world.model, config.plate, config.box.size, config.palm_size)
    transforms = scene.transforms(s)
    assert [t["child_frame_id"] for t in transforms] == [*LINKS, "plate", "box", "palm"]
    assert {t["parent_frame_id"] for t in transforms} == {BASE_FRAME}
    flange = transforms[LINKS.index("panda_link8")]["translation"]
    ee = s.transform_ee_to_base[:3, 3]
    plate = transforms[len(LINKS)]["translation"]
    normal = s.transform_ee_to_base[:3, 2]
    assert [plate["x"], plate["y"], plate["z"]] == pytest.approx(ee + normal * config.plate.offset, abs=1e-9)
    assert np.linalg.norm([flange["x"], flange["y"], flange["z"]]) > 0.3  # the flange, away from the base
    box = transforms[-2]["translation"]
    assert [box["x"], box["y"], box["z"]] == pytest.approx(s.box_position)
    update = scene.scene_update(s)
    entities = {e["id"]: e for e in update["entities"]}
    assert list(entities) == ["robot", "plate", "box", "palm", "forces"]
    assert entities["box"]["metadata"] == [{"key": "state", "value": state_of(s)}]
    assert rgb_of(entities["box"]["cubes"][0]["color"]) == COLOURS[state_of(s)]
    assert len(entities["robot"]["lines"][0]["points"]) == 1 + len(LINKS)  # the base and every link
    assert len(entities["forces"]["arrows"]) == 3
