"""Figures of trials for lab reports (matplotlib, Agg backend; PNG and SVG).

A trial's figure: five panels over time — f_n with the band; the friction ratio |f_t|/(mu f_n)
with the cone margin alpha and the cone (1); the slip of the box in the palm with the 2 cm limit;
the box height; the robot's speed — with a marker where the person let go and one where a drop,
reflex or time-out ended the trial. The summary: successes per participant and controller.
Each panel's axes carries a gid (f_n, friction_ratio, slip, box_height, robot_speed) and each
line a label, so tests read the figure's data back.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # no display: files only
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

PANELS = ("f_n", "friction_ratio", "slip", "box_height", "robot_speed")
FORMATS = ("png", "svg")


def trial_figure(trace, result, label: str = "") -> Figure:
    """The figure of one trial from its Trace and TrialResult."""
    a = trace.arrays()
    t = a["time"]
    fig = Figure(figsize=(8.0, 10.0))
    axes = fig.subplots(len(PANELS), 1, sharex=True)
    fig.subplots_adjust(left=0.1, right=0.98, top=0.96, bottom=0.05, hspace=0.1)  # fixed: layout engines cost 40 %
    verdict = "success" if result.success else f"NO: {result.reason}"
    who = f"{label}, " if label else ""
    fig.suptitle(
        f"Trial {result.index + 1}: {who}{result.participant} try {result.attempt} (seed {result.seed}) — {verdict}",
        fontsize=10,
    )

    ax = axes[0]
    ax.fill_between(t, a["f_n_min"], a["f_n_max"], color="tab:green", alpha=0.15, label="band [f_n_min, f_n_max]")
    ax.plot(t, a["f_n"], color="tab:red", lw=1.0, label="f_n")
    ax.set_ylabel("f_n (N)")

    ax = axes[1]
    ax.plot(t, a["friction_ratio"], color="tab:purple", lw=1.0, label="|f_t|/(mu f_n)")
    ax.axhline(trace.alpha, color="gray", ls="--", lw=0.8, label=f"cone margin alpha = {trace.alpha:g}")
    ax.axhline(1.0, color="black", ls=":", lw=0.8, label="cone (1)")
    ax.set_ylabel("|f_t|/(mu f_n)")

    ax = axes[2]
    ax.plot(t, a["slip"] * 1e3, color="tab:brown", lw=1.0, label="slip in the palm")
    ax.axhline(trace.max_slip * 1e3, color="black", ls=":", lw=0.8, label=f"drop at {trace.max_slip * 1e3:g} mm")
    ax.set_ylabel("slip (mm)")

    ax = axes[3]
    ax.plot(t, a["box_height"], color="tab:blue", lw=1.0, label="box height")
    ax.set_ylabel("box z (m)")

    ax = axes[4]
    ax.plot(t, a["robot_speed"], color="tab:orange", lw=1.0, label="|v| robot")
    ax.set_ylabel("|v| (m/s)")
    ax.set_xlabel("time (s)")

    for gid, ax in zip(PANELS, axes):
        ax.set_gid(gid)
        ax.grid(alpha=0.3)
        if trace.let_go is not None:
            ax.axvline(trace.let_go, color="tab:green", ls="--", lw=1.0, label="person let go")
        if trace.failure is not None:
            ax.axvline(trace.failure, color="tab:red", lw=1.2, label=_failure_label(trace.reason))
        ax.legend(loc="upper left", fontsize=7, ncols=2)
    return fig


def _failure_label(reason: str) -> str:
    return reason.split(":")[0] if reason else "end"  # "dropped", "robot reflex", "time limit", "no grip"


def save(fig: Figure, stem: Path) -> dict[str, str]:
    """PNG and SVG next to each other: {format: path}."""
    stem.parent.mkdir(parents=True, exist_ok=True)
    paths = {}
    for fmt in FORMATS:
        path = stem.with_suffix(f".{fmt}")
        fig.savefig(path, dpi=110)
        paths[fmt] = str(path)
    return paths


def save_trial_figure(trace, result, stem: Path, label: str = "") -> dict[str, str]:
    return save(trial_figure(trace, result, label), Path(stem))


def summary_figure(results_by_controller: dict[str, list]) -> Figure:
    """Successes per participant (x) and controller (bars): the table at a glance."""
    names = list(results_by_controller)
    people = list(dict.fromkeys(r.participant for rs in results_by_controller.values() for r in rs))
    fig = Figure(figsize=(max(5.0, 1.6 * len(people) + 2), 3.6), layout="constrained")
    ax = fig.subplots()
    ax.set_gid("summary")
    width = 0.8 / max(1, len(names))
    for k, name in enumerate(names):
        rs = results_by_controller[name]
        ok = [sum(r.success for r in rs if r.participant == p) for p in people]
        of = [sum(1 for r in rs if r.participant == p) for p in people]
        x = [i + (k - (len(names) - 1) / 2) * width for i in range(len(people))]
        bars = ax.bar(x, ok, width, label=f"{name + ': ' if name else ''}{sum(ok)}/{sum(of)} succeeded")
        ax.bar_label(bars, labels=[f"{o}/{n}" for o, n in zip(ok, of)], fontsize=8)
    ax.set_xticks(range(len(people)), people)
    ax.set_ylabel("successful trials")
    ax.yaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_ylim(
        0,
        max([1] + [sum(1 for r in rs if r.participant == p) for rs in results_by_controller.values() for p in people])
        + 0.5,
    )
    ax.set_title("Success per participant" + (" and controller" if len(names) > 1 else ""), fontsize=10)
    ax.legend(fontsize=8)
    return fig


def save_summary_figure(results_by_controller: dict[str, list], plots_dir: str | Path) -> dict[str, str]:
    return save(summary_figure(results_by_controller), Path(plots_dir) / "summary")
