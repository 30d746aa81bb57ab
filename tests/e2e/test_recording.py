"""Recordings (MCAP) and figures of trials: read back with the mcap reader, checked against the
simulation that made them."""

import signal
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from mcap.reader import make_reader

from sim.controllers.interface import LiftingParams
from sim.procedures.experiment import plan
from sim.procedures.trial import Trial
from sim.recording import reader
from sim.recording.figures import PANELS, summary_figure, trial_figure
from sim.recording.playback import Playback
from sim.recording.trial import TrialObserver, TrialOutputs
from sim.recording.writer import Recording

LAB_TOPICS = {
    "/franka_state_controller/F_ext": "geometry_msgs/WrenchStamped",
    "/joint_states": "sensor_msgs/JointState",
    "/cartesian_velocity_controller/command": "geometry_msgs/Twist",
    "/object_pose": "geometry_msgs/PoseStamped",
    "/human_hand_pose": "geometry_msgs/PoseStamped",
    "/contact_state": "hri_lab/ContactState",
    "/lifting_state": "hri_lab/LiftingState",
    "/trial": "hri_lab/TrialOutcome",
    "/trial_state": "hri_lab/TrialState",
}


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    """A hasty trial at alpha 0.8 (it drops the box after ~3 s: short, and it has both markers), recorded and
    plotted, with the box's simulated path kept step by step."""
    out = tmp_path_factory.mktemp("trial")
    index, person, attempt, seed = plan(9, "hasty", 0)[0]
    trial = Trial(person, seed, index=index, attempt=attempt, params=LiftingParams(alpha=0.8))
    observer = TrialObserver(trial, TrialOutputs(str(out), str(out)))
    path = {}

    def watch(t):
        observer(t)
        path[round(t.world.time * 1e9)] = t.world.box.position.copy()

    trial.observer = watch
    result = trial.run()
    result.files = observer.finish(result)
    return result, observer.trace, path


def test_recorded_trial_has_the_channels_schemas_and_counts(recorded):
    result, _, _ = recorded
    with open(result.files["recording"], "rb") as f:
        summary = make_reader(f).get_summary()
    channels = {
        c.topic: (summary.schemas[c.schema_id].name, c.message_encoding, summary.schemas[c.schema_id].encoding)
        for c in summary.channels.values()
    }
    counts = {summary.channels[cid].topic: n for cid, n in summary.statistics.channel_message_counts.items()}
    assert channels == {
        **{t: (kind, "json", "jsonschema") for t, kind in LAB_TOPICS.items()},
        "/tf": ("foxglove.FrameTransform", "json", "jsonschema"),
        "/scene": ("foxglove.SceneUpdate", "json", "jsonschema"),
    }
    # decimation: the topics every 10 ms, /tf and /scene every 40 ms of the trial's steps (from t = 1 ms)
    steps = result.steps
    topics_n, scene_n = (steps - 1) // 10 + 1, (steps - 1) // 40 + 1
    assert counts == {**{t: topics_n for t in LAB_TOPICS}, "/tf": 11 * scene_n, "/scene": scene_n}
    frames = {m.data["child_frame_id"] for m in reader.messages(result.files["recording"], ["/tf"])}
    assert frames == {*(f"panda_link{i}" for i in range(1, 9)), "plate", "box", "palm"}
    assert reader.metadata(result.files["recording"])["end"]["trial"]["reason"] == result.reason


def test_replayed_box_path_is_the_simulated_one(recorded):
    result, _, path = recorded
    playback = Playback(result.files["recording"])
    assert len(playback.frames) == (result.steps - 1) // 40 + 1
    for frame in playback.frames:
        simulated = path[round(playback.start + frame.time * 1e9)]
        np.testing.assert_allclose(frame.poses["box"][0], simulated, atol=1e-12)
    for m in reader.messages(result.files["recording"], ["/object_pose"]):
        p = m.data["pose"]["position"]
        np.testing.assert_allclose([p["x"], p["y"], p["z"]], path[m.log_time], atol=1e-12)
    # the last message of /object_pose at the playback's end is the recorded one
    last = playback.message_at("/object_pose", playback.duration + 1.0)
    assert last["header"]["stamp"]["sec"] == int(result.duration)


def test_bag_info_prints_what_ros2_bag_info_does(recorded):
    result, _, _ = recorded
    text = reader.format_info(reader.info(result.files["recording"]))
    n = (result.steps - 1) // 10 + 1
    assert "Storage id:        mcap\n" in text
    assert f"Duration:          {(n - 1) * 0.01:.3f}s" in text  # first to last sample of the topics
    assert f"Topic: /franka_state_controller/F_ext         | Type: geometry_msgs/WrenchStamped | Count: {n} |" in text
    assert "Topic: /scene " in text
    assert "Type: foxglove.SceneUpdate " in text


def test_trial_figure_has_the_panels_and_markers(recorded):
    result, trace, _ = recorded
    assert set(result.files) == {"recording", "png", "svg"}
    fig = trial_figure(trace, result)
    axes = {ax.get_gid(): ax for ax in fig.axes}
    assert tuple(axes) == PANELS
    a = trace.arrays()
    lines = {gid: {line.get_label(): line for line in ax.get_lines()} for gid, ax in axes.items()}
    np.testing.assert_array_equal(lines["f_n"]["f_n"].get_ydata(), a["f_n"])
    np.testing.assert_array_equal(lines["slip"]["slip in the palm"].get_ydata(), a["slip"] * 1e3)
    np.testing.assert_array_equal(lines["robot_speed"]["|v| robot"].get_xdata(), a["time"])
    assert lines["friction_ratio"]["cone margin alpha = 0.8"].get_ydata()[0] == 0.8
    assert lines["slip"]["drop at 20 mm"].get_ydata()[0] == 20.0
    band = axes["f_n"].collections[0].get_paths()[0].vertices[:, 1]
    assert band.min() == pytest.approx(10.0)
    assert band.max() == pytest.approx(15.0)
    # markers: the person let go (after the robot's grip), and the drop at the end of the trial
    assert 0.0 < trace.let_go < result.duration
    for gid in PANELS:
        assert lines[gid]["person let go"].get_xdata()[0] == trace.let_go
        assert lines[gid]["dropped"].get_xdata()[0] == result.duration
    # the signals are the trial's: the slip reaches the rule's 2 cm, the box was lifted off the start height
    assert a["slip"][-1] == pytest.approx(result.slip)
    assert a["f_n"][a["time"] >= trace.let_go].min() == pytest.approx(result.f_n_min, abs=0.5)


def test_summary_figure_counts_successes_per_participant_and_controller():
    from sim.procedures.trial import TrialResult

    def r(person, ok):
        return TrialResult(0, person, 1, 0, ok, 1.0, 0, 0, 0, 0, "")

    fig = summary_figure(
        {
            "sp": [r("calm", True), r("calm", True), r("hasty", False)],
            "patch": [r("calm", True), r("calm", False), r("hasty", True)],
        }
    )
    ax = fig.axes[0]
    heights = [p.get_height() for p in ax.patches]
    assert heights == [2, 0, 1, 1]  # sp: calm 2, hasty 0; patch: calm 1, hasty 1
    assert [t.get_text() for t in ax.get_xticklabels()] == ["calm", "hasty"]


def test_size_cap_stops_a_runaway_recording_and_the_file_is_finished(tmp_path):
    from sim.world import World

    world = World()
    recording = Recording(tmp_path / "cap.mcap", world.config, max_bytes=1, flush_period=0.02)
    kept = [recording.add(world.snapshot()) for _ in range(40) if not world.step()]
    assert kept[0]
    assert not kept[-1]
    assert "recording stopped: the file reached" in recording.stopped
    bag = reader.info(tmp_path / "cap.mcap")
    assert bag.complete
    assert bag.messages > 0


def test_a_recording_cut_short_is_readable(tmp_path):
    """The writer's process is killed (SIGKILL) mid-recording: the chunks it flushed are read."""
    path = tmp_path / "cut.mcap"
    script = textwrap.dedent(f"""
        import sys, time
        from sim.world import World
        from sim.recording.writer import Recording
        world = World()
        recording = Recording({str(path)!r}, world.config, flush_period=0.1)
        for _ in range(500):
            world.step()
            recording.add(world.snapshot())
        print("written", flush=True)
        time.sleep(60)
    """)
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip() == "written"
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    bag = reader.info(path)
    assert not bag.complete
    counts = {t.name: t.count for t in bag.topics}
    assert counts["/joint_states"] >= 40  # of 50 written: all but the last 0.1 s flush
    assert "cut short" in reader.format_info(bag)
    times = [m.data["header"]["stamp"]["nanosec"] for m in reader.messages(path, ["/joint_states"])]
    assert times == sorted(times)


def test_experiment_cli_records_and_plots_every_trial(tmp_path):
    from app.cli.main import main

    assert (
        main(
            [
                "experiment",
                "--trials",
                "1",
                "--participant",
                "hasty",
                "--set",
                "alpha=0.8",
                "--jobs",
                "1",
                "--quiet",
                "--record",
                str(tmp_path / "rec"),
                "--plots",
                str(tmp_path / "fig"),
            ]
        )
        == 0
    )
    assert sorted(p.name for p in (tmp_path / "rec").iterdir()) == ["trial01_hasty_1.mcap"]
    assert sorted(p.name for p in (tmp_path / "fig").iterdir()) == [
        "summary.png",
        "summary.svg",
        "trial01_hasty_1.png",
        "trial01_hasty_1.svg",
    ]
