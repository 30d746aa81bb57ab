"""sim/recording/trial.py: the outputs' file names, the trace sampled every TRACE_PERIOD of
simulated time from the world's own state, the trial's recording with its /trial_state, and what
`finish` leaves (the failure marked, the recording closed with the result, the figure's files)."""

import pytest

from sim.person.participants import PARTICIPANTS
from sim.procedures.trial import Trial
from sim.recording.reader import messages, metadata
from sim.recording.trial import TRACE_PERIOD, TrialObserver, TrialOutputs
from sim.recording.writer import TRIAL_STATE


def test_the_outputs_name_the_trial_and_the_controller():
    assert TrialOutputs().stem(6, "hasty", 1) == "trial07_hasty_1"
    assert TrialOutputs(prefix="sp_").stem(0, "careful", 3) == "sp_trial01_careful_3"
    assert not TrialOutputs().wanted
    assert TrialOutputs(plots_dir="p").wanted
    assert TrialOutputs(record_dir="r").wanted


@pytest.fixture(scope="module")
def observed(tmp_path_factory):
    """0.1 s of a trial (100 steps), recorded and traced."""
    folder = tmp_path_factory.mktemp("trial")
    trial = Trial(PARTICIPANTS["calm"], seed=3, index=1, attempt=2)
    observer = trial.observer = TrialObserver(trial, TrialOutputs(record_dir=str(folder), plots_dir=str(folder)))
    heights = {}  # simulated time (ms) -> the box's height then, read from the world after each step
    for _ in range(100):
        trial.step()
        heights[round(trial.world.time * 1e3)] = float(trial.world.box.position[2])
    return trial, observer, folder, heights


def test_the_trace_follows_the_world_every_trace_period(observed):
    trial, observer, _, heights = observed
    trace = observer.trace
    start = trace.time[0]
    steps = [round((b - a) / TRACE_PERIOD, 6) for a, b in zip(trace.time, trace.time[1:])]
    assert steps == [1.0] * (len(trace.time) - 1)  # one sample every 5 ms of simulated time
    # the first step ends at 1 ms; steps 1..100 (1 ms each) are sampled at 1, 6, ..., 96 ms: 20 samples
    assert start == pytest.approx(trial.world.config.dt)
    assert len(trace.time) == 20
    assert trace.f_n_max[-1] == pytest.approx(trial.world.params.f_n_max)
    assert trace.f_n_max[-1] - trace.f_n_min[-1] == pytest.approx(trial.world.params.f_n_band)
    assert trace.box_height == [heights[round(t * 1e3)] for t in trace.time]
    assert len(set(trace.box_height)) > 1  # the box moved: the samples are not one value repeated
    assert trace.alpha == trial.world.params.alpha
    assert trace.max_slip == trial.rules.max_slip
    assert set(trace.arrays()) == {
        "time",
        "f_n",
        "f_n_min",
        "f_n_max",
        "friction_ratio",
        "slip",
        "box_height",
        "robot_speed",
    }


def test_finish_closes_the_recording_with_the_result_and_writes_the_figure(observed):
    trial, observer, folder, _ = observed
    result = trial.result()
    result.success, result.reason, result.duration = False, "dropped: slipped 2 cm in the palm", 0.1
    paths = observer.finish(result)
    assert observer.trace.failure == 0.1
    assert observer.trace.reason.startswith("dropped")
    assert paths == {
        "recording": str(folder / "trial02_calm_2.mcap"),
        "png": str(folder / "trial02_calm_2.png"),
        "svg": str(folder / "trial02_calm_2.svg"),
    }
    assert all((folder / p).exists() for p in paths.values())
    states = [m.data for m in messages(paths["recording"], [TRIAL_STATE])]
    assert len(states) >= 10  # one per 10 ms of the 0.1 s (the recording's decimation)
    assert states[-1]["box_height"] == pytest.approx(float(trial.world.box.position[2]), abs=1e-3)
    assert states[-1]["human_phase"] == trial.world.human.phase
    assert metadata(paths["recording"])["end"]["trial"]["reason"] == result.reason
