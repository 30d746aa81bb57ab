"""sim/recording/figures.py: a trial's five panels carry its signals (read back by gid and label),
the band, the cone margin, the slip limit in mm and the markers; the summary counts successes per
participant and controller; both saved as PNG and SVG."""

from types import SimpleNamespace

import numpy as np

from sim.recording.figures import PANELS, save_summary_figure, save_trial_figure, summary_figure, trial_figure
from sim.recording.trial import Trace


def trace() -> Trace:
    t = Trace(alpha=0.5, max_slip=0.02, let_go=0.2, failure=0.3, reason="dropped: slipped 2 cm in the palm")
    for i in range(4):
        t.time.append(0.1 * i)
        t.f_n.append(10.0 + i)
        t.f_n_min.append(10.0)
        t.f_n_max.append(15.0)
        t.friction_ratio.append(0.1 * i)
        t.slip.append(0.001 * i)
        t.box_height.append(0.3 + 0.01 * i)
        t.robot_speed.append(0.05 * i)
    return t


def result(participant="calm", success=False, index=0):
    return SimpleNamespace(
        index=index, participant=participant, attempt=2, seed=9, success=success, reason="dropped: slipped"
    )


def line(ax, label: str):
    (found,) = [ln for ln in ax.get_lines() if ln.get_label() == label]
    return found


def test_a_trials_panels_carry_its_signals_and_markers():
    fig = trial_figure(trace(), result(), label="sp")
    axes = {ax.get_gid(): ax for ax in fig.axes}
    assert list(axes) == list(PANELS)
    assert fig._suptitle.get_text() == "Trial 1: sp, calm try 2 (seed 9) — NO: dropped: slipped"
    assert list(line(axes["f_n"], "f_n").get_ydata()) == [10.0, 11.0, 12.0, 13.0]
    assert list(line(axes["friction_ratio"], "cone margin alpha = 0.5").get_ydata()) == [0.5, 0.5]
    assert list(line(axes["slip"], "slip in the palm").get_ydata()) == [0.0, 1.0, 2.0, 3.0]  # mm
    assert list(line(axes["slip"], "drop at 20 mm").get_ydata()) == [20.0, 20.0]
    assert np.allclose(line(axes["robot_speed"], "|v| robot").get_ydata(), [0.0, 0.05, 0.1, 0.15])
    for ax in fig.axes:
        assert list(line(ax, "person let go").get_xdata()) == [0.2, 0.2]
        assert list(line(ax, "dropped").get_xdata()) == [0.3, 0.3]  # the failure, named by its reason's head
    band = [c for c in axes["f_n"].collections if c.get_label() == "band [f_n_min, f_n_max]"]
    assert len(band) == 1


def test_the_summary_counts_successes_per_participant_and_controller():
    runs = {
        "sp": [result("calm", True), result("calm", False), result("hasty", True)],
        "mine": [result("calm", False), result("hasty", False)],
    }
    fig = summary_figure(runs)
    (ax,) = fig.axes
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["sp: 2/3 succeeded", "mine: 0/2 succeeded"]
    assert [t.get_text() for t in ax.get_xticklabels()] == ["calm", "hasty"]
    bars = [[p.get_height() for p in c] for c in ax.containers]
    assert bars == [[1, 1], [0, 0]]
    assert sorted(t.get_text() for t in ax.texts) == ["0/1", "0/1", "1/1", "1/2"]


def test_both_are_saved_as_png_and_svg(tmp_path):
    paths = save_trial_figure(trace(), result(success=True), tmp_path / "figs" / "trial01_calm_2")
    assert paths == {"png": str(tmp_path / "figs/trial01_calm_2.png"), "svg": str(tmp_path / "figs/trial01_calm_2.svg")}
    assert (tmp_path / "figs/trial01_calm_2.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "— success" in (tmp_path / "figs/trial01_calm_2.svg").read_text()
    summary = save_summary_figure({"": [result(success=True)]}, tmp_path)
    assert sorted(summary) == ["png", "svg"]
    assert all(p.startswith(str(tmp_path / "summary")) for p in summary.values())
