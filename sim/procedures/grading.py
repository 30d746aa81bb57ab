"""`hri-lab grade FILE.py`: the fixed, documented battery a student's controller is graded with.

1. Probes (5 points each): the controller alone, fed constant wrenches for 1 s from rest (so input
   filters and rate limits settle), at the side pose (EE x down, plate normal = base +y) and at a
   second pose turned 90 deg about base z (a twist left in the EE frame fails there):
   start/stop semantics; stopped -> zero twist; below the band -> along +n; the same at the second
   pose; inside the band -> still; above -> along -n; friction beyond the cone while the person
   lifts -> up, with the person; inside the cone -> no tangential motion; a moment -> comply.
2. The experiment (5 points per trial of the calm and average participants): the nine Table 1
   trials; the hasty participant's trials are reported with 0 points (the SP method is not
   expected to keep up with them; see README).
3. Robustness (10 points each): a calm trial with three times the sensor noise; a calm trial in
   which the person jerks the box 3 cm sideways in 0.3 s while carrying it.
The controller runs guarded (sim/controllers/guard.py): exceptions, bad twists and slow steps cost the items
they break, with the reason in the report. Deterministic for a given seed (timing aside).
"""
from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field
from typing import Callable

import numpy as np

from sim.controllers.interface import Controller, LiftingParams, start_lifting
from sim.procedures.experiment import Trial, TrialResult, run_experiment, trial_seed
from sim.controllers.guard import ControllerFault
from sim.person.human import PARTICIPANTS
from sim.physics.sensor import SensorParams
from sim.world import WorldConfig

PASS_MARK = 60.0  # %
# the side pose's rotation (EE -> base): x = -z_b (down), y = -x_b, z = +y_b (toward the person)
SIDE_ROTATION = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0]])
TURNED_ROTATION = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]) @ SIDE_ROTATION


@dataclass
class Item:
    section: str
    name: str
    points: float
    max_points: float
    detail: str = ""


@dataclass
class Report:
    controller: str
    seed: int
    items: list[Item] = field(default_factory=list)

    @property
    def points(self) -> float:
        return sum(i.points for i in self.items)

    @property
    def max_points(self) -> float:
        return sum(i.max_points for i in self.items)

    @property
    def score(self) -> float:
        return 100.0 * self.points / self.max_points if self.max_points else 0.0

    @property
    def passed(self) -> bool:
        return self.score >= PASS_MARK

    def as_dict(self) -> dict:
        return {"controller": self.controller, "seed": self.seed, "points": self.points, "max_points": self.max_points,
                "score": round(self.score, 1), "pass_mark": PASS_MARK, "passed": self.passed,
                "items": [asdict(i) for i in self.items]}

    def text(self) -> str:
        lines = [f"hri-lab grade: {self.controller}, seed {self.seed}", " points  item"]
        for i in self.items:
            mark = "ok" if i.points == i.max_points else ("--" if i.max_points == 0 else "FAILED")
            lines.append(f" {i.points:>4g}/{i.max_points:<3g} {i.section}: {i.name} — {mark}" + (f": {i.detail}" if i.detail else ""))
        verdict = "PASS" if self.passed else "FAIL"
        lines.append(f"score: {self.points:g}/{self.max_points:g} = {self.score:.1f} % (pass mark {PASS_MARK:g} %): {verdict}")
        return "\n".join(lines)

    def json(self) -> str:
        return json.dumps(self.as_dict(), indent=2)


# --- 1. probes ----------------------------------------------------------------------------------
def _transform(rotation: np.ndarray) -> np.ndarray:
    transform = np.eye(4)
    transform[:3, :3] = rotation
    transform[:3, 3] = [0.6, 0.15, 0.35]
    return transform


def _lifting_params() -> LiftingParams:
    params = LiftingParams()
    start_lifting(params, 10.0)  # band [10, 15]
    return params


def _settle(controller: Controller, wrench, rotation, params: LiftingParams, steps: int = 1000) -> np.ndarray:
    controller.reset()
    wrench, transform = np.array(wrench, float), _transform(rotation)
    twist = np.zeros(6)
    for _ in range(steps):
        twist = np.asarray(controller.step(wrench.copy(), transform.copy(), params, 1e-3), float)
    return twist


def _cos(a: np.ndarray, b: np.ndarray) -> float:
    na, nb = np.linalg.norm(a), np.linalg.norm(b)
    return float(a @ b / (na * nb)) if na > 1e-12 and nb > 1e-12 else 0.0


def _fmt(v: np.ndarray) -> str:
    return "[" + ", ".join(f"{x:.3f}" for x in v) + "]"


def _probe_start_stop(controller) -> str:
    params = LiftingParams()
    controller.start(params, 10.0)
    if (params.f_n_min, params.f_n_max, params.running) != (10.0, 15.0, True):
        return f"after start(10): f_n_min={params.f_n_min}, f_n_max={params.f_n_max}, running={params.running}; expected 10, 15, True"
    controller.stop(params)
    if (params.f_n_min, params.running) != (0.0, False):
        return f"after stop(): f_n_min={params.f_n_min}, running={params.running}; expected 0, False"
    return ""


def _probe_stopped(controller) -> str:
    params = LiftingParams()
    twist = _settle(controller, [0, 0, 3.0, 0, 0, 0], SIDE_ROTATION, params)
    return "" if np.linalg.norm(twist) < 1e-3 else f"stopped, yet commands {_fmt(twist)}"


def _along(direction_name: str, direction: np.ndarray, f_n: float, rotation: np.ndarray) -> Callable:
    def probe(controller) -> str:
        params = _lifting_params()
        twist = _settle(controller, [0, 0, f_n, 0, 0, 0], rotation, params)
        v, w = twist[:3], twist[3:]
        if np.linalg.norm(v) < 1e-3:
            return f"f_n = {f_n} N: no motion ({_fmt(twist)}); expected along {direction_name}"
        if _cos(v, direction) < 0.95:
            return f"f_n = {f_n} N: moves along {_fmt(v)} (base frame); expected along {direction_name} = {_fmt(direction)}"
        if np.linalg.norm(v) > params.v_max + 1e-6 or np.linalg.norm(w) > 0.05:
            return f"f_n = {f_n} N: twist {_fmt(twist)} is beyond v_max or turns"
        return ""

    return probe


def _probe_inside_band(controller) -> str:
    twist = _settle(controller, [0.5, -0.5, 12.0, 0, 0, 0], SIDE_ROTATION, _lifting_params())
    return "" if np.linalg.norm(twist[:3]) < 2e-3 else f"f_n = 12 N (inside [10, 15]) but moves {_fmt(twist)}"


def _probe_lift(controller) -> str:
    # the person lifts: the plate's friction on the box points down = EE +x at the side pose, 8 N > 0.8*0.5*12
    twist = _settle(controller, [8.0, 0, 12.0, 0, 0, 0], SIDE_ROTATION, _lifting_params())
    normal = SIDE_ROTATION[:, 2]
    v_t = twist[:3] - (twist[:3] @ normal) * normal
    if np.linalg.norm(v_t) < 0.01 or _cos(v_t, np.array([0, 0, 1.0])) < 0.9:
        return f"friction 8 N down beyond the cone: tangential motion {_fmt(v_t)}; expected up (against f_t, with the person)"
    return ""


def _probe_hold(controller) -> str:
    twist = _settle(controller, [3.0, 0, 12.0, 0, 0, 0], SIDE_ROTATION, _lifting_params())
    normal = SIDE_ROTATION[:, 2]
    v_t = twist[:3] - (twist[:3] @ normal) * normal
    return "" if np.linalg.norm(v_t) < 2e-3 else f"friction 3 N inside the cone, yet moves tangentially {_fmt(v_t)}"


def _probe_moment(controller) -> str:
    twist = _settle(controller, [0, 0, 12.0, 0.5, 0, 0], SIDE_ROTATION, _lifting_params())
    expected = -SIDE_ROTATION[:, 0]
    if np.linalg.norm(twist[3:]) < 0.01 or _cos(twist[3:], expected) < 0.9:
        return f"moment 0.5 Nm about EE x: turns {_fmt(twist[3:])}; expected to comply, along {_fmt(expected)}"
    return ""


PROBES = [
    ("start and stop set the band [force, force + 5] and running", _probe_start_stop),
    ("stopped: zero twist", _probe_stopped),
    ("below the band: press along +n", _along("+n", SIDE_ROTATION[:, 2], 4.0, SIDE_ROTATION)),
    ("below the band at a turned pose: +n in the base frame", _along("+n", TURNED_ROTATION[:, 2], 4.0, TURNED_ROTATION)),
    ("inside the band: hold still", _probe_inside_band),
    ("above the band: release along -n", _along("-n", -SIDE_ROTATION[:, 2], 20.0, SIDE_ROTATION)),
    ("the person lifts (friction beyond the cone): follow up", _probe_lift),
    ("friction inside the cone: no tangential motion", _probe_hold),
    ("a moment at the plate: comply", _probe_moment),
]


def probe_items(factory: Callable[[], Controller]) -> list[Item]:
    items = []
    for name, probe in PROBES:
        try:
            reason = probe(factory())
        except ControllerFault as fault:
            reason = str(fault).splitlines()[0]
        items.append(Item("probe", name, 0.0 if reason else 5.0, 5.0, reason))
    return items


# --- 2. the experiment ----------------------------------------------------------------------------
def experiment_items(factory: Callable[[], Controller], seed: int, jobs: int = 1, outputs=None) -> list[Item]:
    results = run_experiment(9, seed=seed, controller_factory=factory, jobs=jobs, outputs=outputs)
    if outputs is not None and outputs.plots_dir:
        from sim.recording.figures import save_summary_figure

        save_summary_figure({"": results}, outputs.plots_dir)
    items = []
    for r in results:
        worth = 0.0 if r.participant == "hasty" else 5.0
        detail = r.reason or f"{r.duration:.1f} s, f_n {r.f_n_min:.1f}..{r.f_n_max:.1f} N, slip {r.slip * 1000:.1f} mm"
        if worth == 0.0:
            detail += " (reported, 0 points)"
        items.append(Item("experiment", f"trial {r.index + 1}: {r.participant} #{r.attempt}", worth if r.success else 0.0, worth, detail))
    return items


# --- 3. robustness --------------------------------------------------------------------------------
def _observed(trial: Trial, outputs, prefix: str):
    """Record / plot a robustness trial when asked (files named robust_<prefix>...)."""
    if outputs is None or not outputs.wanted:
        return None
    from dataclasses import replace

    from sim.recording.trial import TrialObserver

    trial.observer = TrialObserver(trial, replace(outputs, prefix=f"robust_{prefix}_"))
    return trial.observer


def _noisy_trial(factory, seed: int, outputs=None) -> TrialResult:
    config = WorldConfig(sensor=SensorParams(force_noise_std=1.5, moment_noise_std=0.15))
    trial = Trial(PARTICIPANTS["calm"], seed, factory(), config=config)
    observer = _observed(trial, outputs, "noise")
    result = trial.run()
    if observer:
        result.files = observer.finish(result)
    return result


def _pull_trial(factory, seed: int, outputs=None) -> TrialResult:
    """2 s into the carry the person jerks the box 3 cm along the carry in 0.3 s (0.1 m/s on top of the path)."""
    trial = Trial(PARTICIPANTS["calm"], seed, factory())
    observer = _observed(trial, outputs, "pull")
    human = trial.world.human
    pulled = 0
    direction = np.asarray(human.path_spec.carry_direction, float)
    while trial.step():
        if human.phase == "carrying" and human.phase_time >= 2.0 and pulled < 300:
            human.start = human.start + direction * 0.0001
            pulled += 1
    result = trial.result()
    if observer:
        result.files = observer.finish(result)
    return result


def robustness_items(factory: Callable[[], Controller], seed: int, outputs=None) -> list[Item]:
    items = []
    for name, run in (("three times the sensor noise (calm trial)", _noisy_trial),
                      ("a sudden 3 cm pull while carrying (calm trial)", _pull_trial)):
        result = run(factory, trial_seed(seed, 100 + len(items)), outputs)
        items.append(Item("robustness", name, 10.0 if result.success else 0.0, 10.0, result.reason))
    return items


def grade(factory: Callable[[], Controller], name: str, seed: int = 0, jobs: int = 1, outputs=None) -> Report:
    """outputs: a TrialOutputs (sim/recording/trial.py) to record and plot every trial."""
    report = Report(name, seed)
    report.items += probe_items(factory)
    report.items += experiment_items(factory, seed, jobs, outputs)
    report.items += robustness_items(factory, seed, outputs)
    return report


