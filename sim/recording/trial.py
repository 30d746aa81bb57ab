"""What a trial leaves besides its table row: an MCAP recording and a figure (`--record DIR`,
`--plots DIR`). A TrialObserver is called by the Trial after every step; it records the decimated
Snapshots and keeps a trace of the figure's signals (every TRACE_PERIOD s, and at the events)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from sim.messages import header
from sim.spatial import norm3

TRACE_PERIOD = 0.005  # s between two samples of a figure's signals (200 Hz)


@dataclass(frozen=True)
class TrialOutputs:
    """Where a trial's recording and figure go (None: not made). `prefix` names a comparison's controller."""

    record_dir: str | None = None
    plots_dir: str | None = None
    prefix: str = ""
    label: str = ""  # the controller, shown in the figure's title

    def stem(self, index: int, participant: str, attempt: int) -> str:
        """e.g. trial07_hasty_1 (sp_trial07_hasty_1 in a comparison)."""
        return f"{self.prefix}trial{index + 1:02d}_{participant}_{attempt}"

    @property
    def wanted(self) -> bool:
        return bool(self.record_dir or self.plots_dir)


@dataclass
class Trace:
    """A trial's signals over time (SI units) and its events."""

    time: list[float] = field(default_factory=list)  # s
    f_n: list[float] = field(default_factory=list)  # N, plate normal force (true)
    f_n_min: list[float] = field(default_factory=list)  # N, the band
    f_n_max: list[float] = field(default_factory=list)
    friction_ratio: list[float] = field(default_factory=list)  # |f_t| / (mu f_n), mu = the controller's
    slip: list[float] = field(default_factory=list)  # m, the success rule's slip in the palm (max so far)
    box_height: list[float] = field(default_factory=list)  # m, box centre z
    robot_speed: list[float] = field(default_factory=list)  # m/s, |v| of the EE
    alpha: float = 0.8  # the controller's cone margin
    max_slip: float = 0.02  # m, the success rule's limit
    let_go: float | None = None  # s, the person let go of the grasp
    failure: float | None = None  # s, a drop, reflex or time-out ended the trial
    reason: str = ""

    def arrays(self) -> dict[str, np.ndarray]:
        return {
            k: np.asarray(getattr(self, k))
            for k in ("time", "f_n", "f_n_min", "f_n_max", "friction_ratio", "slip", "box_height", "robot_speed")
        }


class TrialObserver:
    """Records and traces one Trial (called after each of its steps)."""

    def __init__(self, trial, outputs: TrialOutputs) -> None:
        self.outputs = outputs
        self.stem = outputs.stem(trial.index, trial.participant.name, trial.attempt)
        self.trace = Trace(alpha=trial.world.params.alpha, max_slip=trial.rules.max_slip)
        self.recording = None
        if outputs.record_dir:
            from sim.recording.writer import Recording

            self.recording = Recording(
                Path(outputs.record_dir) / f"{self.stem}.mcap",
                trial.world.config,
                source="trial",
                model=trial.world.model,
                trial_state=True,
            )
        self._next_trace = 0.0

    def __call__(self, trial) -> None:
        world = trial.world
        if self.trace.let_go is None and world.human.holding_by_contact:
            self.trace.let_go = world.time
        due = world.time >= self._next_trace - 1e-9 or trial.finished
        if not due and self.recording is None:
            return
        plate = world.plate_state
        speed = norm3(world.arm.twist_base[:3])
        if due:
            self._next_trace = world.time + TRACE_PERIOD
            t = self.trace
            t.time.append(world.time)
            t.f_n.append(plate.normal_force)
            t.f_n_min.append(world.params.f_n_min)
            t.f_n_max.append(world.params.f_n_max)
            mu = world.params.mu
            t.friction_ratio.append(plate.friction_ratio / mu if mu > 0 else 0.0)
            t.slip.append(trial.slip)
            t.box_height.append(float(world.box.position[2]))
            t.robot_speed.append(speed)
        if self.recording is not None and (self.recording.due(world.time) or trial.finished):
            snapshot = world.snapshot()
            self.recording.add(
                snapshot,
                trial_state={
                    "header": header(snapshot, ""),
                    "slip": trial.slip,
                    "robot_speed": speed,
                    "box_height": float(world.box.position[2]),
                    "human_phase": world.human.phase,
                    "finished": trial.finished,
                    "reason": trial.reason,
                },
            )

    def finish(self, result) -> dict[str, str]:
        """Close the recording, write the figure; the paths made."""
        paths = {}
        if not result.success and result.reason:
            self.trace.failure, self.trace.reason = result.duration, result.reason
        if self.recording is not None:
            self.recording.close({"trial": result.as_dict()})
            paths["recording"] = str(self.recording.path)
        if self.outputs.plots_dir:
            from sim.recording.figures import save_trial_figure

            paths.update(
                save_trial_figure(self.trace, result, Path(self.outputs.plots_dir) / self.stem, self.outputs.label)
            )
        return paths
