"""The SP law judged inside the trials (app/grading/law_checks.py), the probes as one stream a
file cannot tell from a trial, and the battery that tells SP from followers and probe-detecting
files (docs/grading-battery.md: what each loses)."""

import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from sim.controllers.interface import LiftingParams, start_lifting
from sim.controllers.sp import SPController
from sim.physics.contact import MOMENT_PATCH, NORMAL_FORCE, TANGENTIAL_FORCE

from app.grading.battery import PROBE_PASS_MARK, ROBUSTNESS, battery, new_report, robustness_job, run_items
from app.grading.law_checks import LawWatch
from app.grading.probe_stream import probe_items, start_transform
from app.grading.situations import MidCarryStop

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "controllers"))
import followers
import mutants
import probe_detectors

STOP = len(ROBUSTNESS) - 1  # the pull, then the mid-carry stop
CONE = {"beyond the cone: raise the grip toward f_n_max", "inside the cone margin: no tangential motion"}
MOMENTS = {"a moment in the plate's plane: comply", "a moment about the plate's normal: comply"}
STILL = "inside the band: hold still"
NORMAL = {
    "below the band: press along +n",
    "below the band at another pose: +n in the base frame",
    "above the band: release along -n",
}
# what the followers lose in the probes (docs/grading-battery.md, the outcomes table)
FOLLOWER_PROBES = {STILL} | CONE | MOMENTS


# --- the law checks on hand-made streams --------------------------------------------------------
def stream(steps, f_n=12.0, f_t=(0.0, 0.0, 0.0), m_c=(0.0, 0.0, 0.0), v=(0.0, 0.0, 0.0), w=(0.0, 0.0, 0.0)) -> LawWatch:
    """A watch fed `steps` 1 ms steps of a still plate (normal +y_b, the side pose) with these
    true contact figures (world frame) and this command; lifting at 10 N, mu = alpha = 0.5."""
    params = LiftingParams()
    start_lifting(params, 10.0)
    transform = np.eye(4)
    transform[:3, :3] = [[0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0]]  # z_ee = +y_b
    watch = LawWatch(capacity=16)  # grows as it is fed
    plate = np.zeros(20)  # the plate contact's numbers, in the contact kernel's layout (World.plate_out)
    plate[NORMAL_FORCE], plate[TANGENTIAL_FORCE], plate[MOMENT_PATCH] = f_n, f_t, m_c
    for k in range(steps):
        world = SimpleNamespace(
            time=(k + 1) * 1e-3,
            params=params,
            twist_command=np.array([*v, *w]),
            arm=SimpleNamespace(transform_ee_to_base=transform),
            human=SimpleNamespace(holding_by_contact=True),
            plate_out=plate,
        )
        watch.observe(world)
    return watch


def behaviours(watch: LawWatch) -> set[str]:
    return {f.behaviour for f in watch.findings()}


def test_sp_like_streams_keep_the_law():
    # inside the margin (|f_t| = 2 N < 0.8 * 0.25 * 12 = 2.4 N), in the band, still: nothing to say
    assert stream(1000, f_t=(0, 0, 2.0)).findings() == []
    # beyond the margin (4 N >= 1.3 * 3 N), following against f_t (down) and raising the grip (+y_b)
    assert stream(1000, f_t=(0, 0, 4.0), v=(0, 0.003, -0.05)).findings() == []
    # a moment of 0.5 Nm about x_b, turning against it
    assert stream(1000, m_c=(0.5, 0, 0), w=(-0.4, 0, 0)).findings() == []


def test_inside_the_margin_a_moving_plate_is_named_with_the_time_and_the_distance():
    """2 N of friction at 12 N: 2 / (0.5 * 12) = 0.33 of mu f_n, inside alpha = 0.5; the plate
    moves 10 mm/s along -z_b: in the 0.5 s window 5.0 mm > 2 mm."""
    found = stream(1000, f_t=(0, 0, 2.0), v=(0, 0, -0.01)).findings()
    assert [f.behaviour for f in found] == ["stick"]
    assert (
        "the friction was 0.33 of mu f_n, inside your margin alpha = 0.5, yet the plate moved 5.0 mm along it"
        in found[0].message
    )
    assert found[0].message.startswith(f"at {found[0].time:.1f} s")
    assert found[0].time == pytest.approx(0.2, abs=0.01)
    # 3 mm/s is 1.5 mm in 0.5 s: within the threshold
    assert stream(1000, f_t=(0, 0, 2.0), v=(0, 0.0, -0.003)).findings() == []


def test_the_band_the_cone_the_grip_and_the_moments_each_named():
    assert behaviours(stream(1000, v=(0, 0.01, 0))) == {"band"}  # f_n 12 N in [11, 14]: 5 mm along n in 0.5 s
    assert behaviours(stream(1000, f_n=14.5, v=(0, 0.01, 0))) == set()  # at the band's edge: not judged
    assert behaviours(stream(1000, f_t=(0, 0, 4.0), v=(0, 0.003, 0.05))) == {"follow"}  # with f_t, not against
    assert behaviours(stream(1000, f_t=(0, 0, 4.0), v=(0, 0, -0.05))) == {"grip"}  # follows, grip not raised
    assert behaviours(stream(1000, m_c=(0.5, 0, 0))) == {"moment"}  # held
    assert behaviours(stream(1000, m_c=(0.5, 0, 0), w=(0.4, 0, 0))) == {"moment"}  # turns the wrong way
    assert behaviours(stream(1000, m_c=(0.2, 0, 0))) == set()  # below 0.3 Nm: not judged
    # nothing is judged while the person still grasps the box, or without contact
    assert behaviours(stream(1000, f_n=0.5, f_t=(0, 0, 0.1), v=(0, 0, -0.05))) == set()


def test_the_mid_carry_stop_is_drawn_from_the_seed():
    path = SimpleNamespace(segments=[(None, 2.0), (None, 4.0), (None, 2.0)])
    human = SimpleNamespace(phase="carrying", phase_time=0.0, path=path, start=np.zeros(3), box_level=None)
    trial = SimpleNamespace(world=SimpleNamespace(human=human, config=SimpleNamespace(dt=1e-3)))
    stops = []
    for seed in (1, 2):
        stop = MidCarryStop(np.random.default_rng([seed, 23]))
        stop(trial)
        stops.append(stop.stop_at)
    assert stops[0] != stops[1]
    assert all(2.0 + 0.3 * 4.0 <= s <= 2.0 + 0.7 * 4.0 for s in stops)


# --- the probes: one stream, as a trial reaches a controller --------------------------------------
class Recording(SPController):
    """SP that keeps every input it is given and every twist it commands."""

    log: list = []  # noqa: RUF012 - a pydantic field's or a test double's default, copied or shared on purpose

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        twist = super().step(wrench_ee, transform_ee_to_base, params, dt)
        Recording.log.append((np.array(wrench_ee), np.array(transform_ee_to_base), twist))
        return twist


def recorded(seed):
    Recording.log = []
    items = probe_items(Recording, seed)
    return items, Recording.log


def test_the_probe_stream_has_nothing_constant_still_or_fixed_to_key_on():
    items, log = recorded(0)
    assert all(i.points == i.max_points for i in items)
    wrenches = np.array([w for w, _, _ in log])
    poses = np.array([t for _, t, _ in log])
    # the sensor's noise: no raw input repeats, not even once in a row
    assert not np.any(np.all(wrenches[1:] == wrenches[:-1], axis=1))
    # one controller, never reset between probes, and the pose moves as it commands: still exactly
    # while the command is zero (as a robot is in a trial), else moved by twist dt
    assert len(log) > 10 * 1000
    twists = np.array([t for _, _, t in log])
    moved = np.any(poses[1:] != poses[:-1], axis=(1, 2))
    assert np.array_equal(moved, np.any(twists[:-1] != 0.0, axis=1))
    assert np.allclose(poses[1:, :3, 3] - poses[:-1, :3, 3], twists[:-1, :3] * 1e-3)
    # it starts where a trial's robot starts (the start pose is no tell)
    assert np.array_equal(log[0][1], start_transform())
    # another seed: other noise, other phase lengths
    _, other = recorded(1)
    assert len(other) != len(log)
    assert not np.allclose(other[0][0], log[0][0])


@pytest.mark.parametrize(
    ("cls", "lost"),
    [
        (followers.AdmittanceBand, FOLLOWER_PROBES),
        (followers.NoCone, {STILL} | CONE),
        (probe_detectors.NoiseFree, FOLLOWER_PROBES),
        (probe_detectors.StillPose, FOLLOWER_PROBES),
        (probe_detectors.ResetPattern, FOLLOWER_PROBES),
        (probe_detectors.ElapsedSteps, CONE | MOMENTS),  # SP for its first 2 s: the band's first probes
    ],
)
def test_followers_and_probe_detectors_lose_the_sp_probes(cls, lost):
    """Through the stream a probe-detecting file is the follower it is in the trials: each loses
    the probes of the cone, the band and the moments, below the probes' pass mark."""
    items = probe_items(cls)
    lost_now = {i.name for i in items if i.points < i.max_points}
    if cls is followers.NoCone:  # it follows the sensor's noise sideways: pressing or releasing along
        # n, it may drift off the normal too (which band probes, the noise decides)
        assert lost <= lost_now <= lost | NORMAL
    else:
        assert lost_now == lost
    report = new_report(cls.__name__, 0)
    report.items = items
    assert report.score_of("probe") < PROBE_PASS_MARK


# --- the trials: the law over the whole stream ---------------------------------------------------
@pytest.fixture(scope="module")
def stop_items():
    """The pull-then-stop trial, one per controller (in two processes)."""
    kinds = {
        "sp": SPController,
        "admittance_band": followers.AdmittanceBand,
        "no_cone": followers.NoCone,
        "moments_held": mutants.MomentsHeld,
    }
    jobs = [robustness_job(STOP, make, 0) for make in kinds.values()]
    return dict(zip(kinds, run_items(jobs, workers=2)))


def test_in_the_stop_situation_sp_keeps_the_law_and_followers_creep(stop_items):
    sp = stop_items["sp"]
    assert sp.points == sp.max_points and "not SP" not in sp.detail, sp.detail
    for name in ("admittance_band", "no_cone"):
        item = stop_items[name]
        assert item.points == 0 and item.detail.startswith("carried in"), item.detail  # it carries the box ...
        # ... but moves along the friction inside the margin: named, with the time and the distance
        assert "inside the friction margin: no tangential motion was missing: at " in item.detail
        assert "inside your margin alpha = 0.5, yet the plate moved" in item.detail
    assert "a moment at the plate: comply" in stop_items["admittance_band"].detail
    # the mutant that holds the moments: the turn of the box shows it
    assert stop_items["moments_held"].points == 0
    assert "a moment at the plate: comply was missing" in stop_items["moments_held"].detail


@pytest.fixture(scope="module")
def oracle_report():
    """A file that runs SP exactly while probed (whatever its tell) and follows in the trials:
    probes here, the whole battery's trials and robustness trials in two processes."""
    report = new_report("oracle", 0)
    probe_detectors.PROBING["now"] = True
    try:
        report.items = probe_items(probe_detectors.Oracle)
    finally:
        probe_detectors.PROBING["now"] = False
    report.items += run_items(battery(probe_detectors.Oracle, 0, ("trial", "robustness")), workers=2)
    return report


def test_a_file_that_knows_when_it_is_probed_still_fails(oracle_report):
    assert oracle_report.score_of("probe") == 100.0
    lost = [i for i in oracle_report.items if i.section != "probe"]
    assert lost and all(i.points == 0 and "not SP" in i.detail for i in lost), [(i.name, i.detail) for i in lost]
    assert oracle_report.points == 65.0
    assert oracle_report.max_points == 130.0
    assert not oracle_report.passed
