"""`hri-lab grade FILE.py`: the battery a student's controller is graded with (docs/grading-battery.md).

1. Probes (5 points each): the SP law's situations, as phases of ONE closed-loop stream that
   reaches the controller the way a trial does (ProbeStream): the trial's sensor noise, the
   trial's start pose, moved only as the controller commands, the trial's parameters, wrenches that ramp and hold for
   drawn times. start/stop set the band; stopped -> zero; below the band -> +n (again at another
   pose: the twist must be in the base frame); inside -> still; above -> -n; the band's upper end
   is force + f_n_band; beyond the cone -> follow against f_t and raise the grip; inside the margin ->
   no tangential motion; between the margin alpha mu f_n and the cone mu f_n -> follow; a moment
   in the plate's plane and one about its normal -> comply. Wrenches, times, noise and
   start/stop's force are drawn from the seed (a course's private seed gives numbers students
   never saw).
2. The experiment (5 points per counted trial): the nine Table 1 trials (sim/procedures/trial.py)
   with the lab's default parameters; the participants in COUNTED_PARTICIPANTS count (all three: at
   the default margin alpha 0.5 the reference SP carries each of them). A trial's points need the
   box carried (the world's own state) AND its whole stream within the SP law, judged from the
   true contact and the controller's commands (sim/procedures/law_checks.py).
3. Robustness (10 points each, judged the same way): a calm trial with three times the sensor
   noise; a calm trial in which the person jerks the box 3 cm sideways in 0.3 s while carrying it,
   and later stops mid-carry, holds still 2 s, lets the robot take more of the weight and turns the
   box (sim/procedures/situations.py).
PASS: PASS_MARK % of all points and PROBE_PASS_MARK % of the probes' (the SP method itself).
A plug-in runs sandboxed (sim/controllers/sandbox/): exceptions, bad twists, hangs, crashes and
slow steps cost the items they break, with the reason. The same seed gives the same report.
The battery is a list of jobs (sim/procedures/runner.py): the probes' stream, each trial, each
robustness trial; they run here, in a local pool or on a Dask cluster, with the same report.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from functools import partial

import numpy as np

from sim.controllers.interface import Controller, ControllerFault, LiftingParams
from sim.controllers.plugin import PluginError, PluginFactory
from sim.controllers.sandbox import sandbox_unavailable
from sim.monitor import TrialRules
from sim.person.participants import PARTICIPANTS, Participant
from sim.physics.sensor import SensorParams, WrenchSensor
from sim.procedures.experiment import plan
from sim.procedures.law_checks import BEHAVIOURS, LawWatch
from sim.procedures.report import Item, Report
from sim.procedures.runner import Job, run_jobs
from sim.procedures.situations import MidCarryStop
from sim.procedures.trial import Trial, TrialResult, make_trial, trial_seed
from sim.recording.trial import TrialObserver, TrialOutputs
from sim.robot.panda import PandaModel
from sim.spatial import rotation_exp
from sim.world import WorldConfig

PASS_MARK = 60.0  # % of all points
PROBE_PASS_MARK = 80.0  # % of the probes' points
# The one place that decides which trials count. All three participants count: measured with
# bench/margin_sweep.py (README, "The experiment"), SP at the default margin (alpha 0.5) carries the
# hasty participant too (3/3, slip <= 3.5 mm), and so does every alpha from 0.3 to 0.65; only the old
# default 0.8 dropped it (the margin's choice, not the method's). A submission that drops the hasty
# participant at the defaults follows too late, and that is the SP method's tangential step.
COUNTED_PARTICIPANTS = ("calm", "average", "hasty")
PROBE_POINTS, TRIAL_POINTS, ROBUSTNESS_POINTS = 5.0, 5.0, 10.0


def new_report(
    subject: str, seed: int, sections: tuple[str, ...] = ("probe", "trial", "robustness"), trials: int = 9
) -> Report:
    """An empty report of the battery's sections: a file that cannot be graded is 0 of their points."""
    report = Report(subject, "controller", seed, marks={"": PASS_MARK, "probe": PROBE_PASS_MARK})
    report.full_points = battery_points(sections, trials)
    return report


def battery_points(sections: tuple[str, ...] = ("probe", "trial", "robustness"), trials: int = 9) -> float:
    """What the battery's sections are worth (130 for the whole battery)."""
    counted = sum(person.name in COUNTED_PARTICIPANTS for _, person, _, _ in plan(trials, seed=0))
    return (
        ("probe" in sections) * len(PROBES) * PROBE_POINTS
        + ("trial" in sections) * counted * TRIAL_POINTS
        + ("robustness" in sections) * len(ROBUSTNESS) * ROBUSTNESS_POINTS
    )


# --- 1. probes ----------------------------------------------------------------------------------
# The probes are phases of ONE stream, the way a trial reaches a controller: one controller, reset
# as a world resets it, then stepped without a break; the wrench reaches it through the trial's
# sensor (its noise and filter, sim/physics/sensor.py), ramping from one phase's value to the next
# in a drawn time; the EE->base transform starts where a trial's does and moves only as the controller
# commands (p += v dt, R <- exp(w dt) R); the lifting parameters are the trial's (the lab's defaults, started with
# the trial's force by the controller's own start handler). Each phase holds its wrench for a drawn time; its mean twist over the last
# PROBE_JUDGED s is judged. Nothing in the stream is constant, still, or at a fixed step.
PROBE_RAMP = (0.1, 0.3)  # s a wrench takes to change (drawn per phase)
PROBE_HOLD = (0.5, 0.8)  # s it is then held (drawn per phase)
PROBE_JUDGED = 0.1  # s at a phase's end whose mean twist is judged


class Draw:
    """The probe values of one seed (the same seed, the same numbers)."""

    def __init__(self, seed: int, probe: int) -> None:
        self.rng = np.random.default_rng([seed, 1000 + probe])
        self.force = float(self.rng.uniform(6.0, 20.0))  # N, start/stop's force

    def unit_in_plane(self) -> np.ndarray:
        angle = self.rng.uniform(0.0, 2.0 * np.pi)
        return np.array([np.cos(angle), np.sin(angle), 0.0])

    def uniform(self, low: float, high: float) -> float:
        return float(self.rng.uniform(low, high))


def start_transform() -> np.ndarray:
    """The EE->base transform a trial starts at (the world's start pose, WorldConfig.start_q)."""
    return PandaModel().kinematics(np.array(WorldConfig().start_q))[0].copy()


class ProbeStream:
    """One controller driven through the probes' phases closed loop (see above)."""

    def __init__(self, factory: Callable[[], Controller], seed: int, dt: float = 1e-3) -> None:
        self.factory, self.dt = factory, dt
        self.rng = np.random.default_rng([seed, 999])
        self.sensor = WrenchSensor(SensorParams(), self.rng)  # the trial's sensor
        self.transform = start_transform()  # where a trial's robot starts
        self.wrench = np.zeros(6)  # N, Nm (EE frame): what the plate feels now
        self.controller: Controller | None = None
        self.stopped = LiftingParams()  # after stop: not running
        self.params = LiftingParams()  # started by the controller's own start handler, as in a trial

    @property
    def rotation(self) -> np.ndarray:
        return self.transform[:3, :3].copy()

    def phase(self, wrench, params: LiftingParams) -> np.ndarray:
        """Ramp the felt wrench to `wrench` (EE frame) and hold it; the mean twist (base frame)
        over the phase's last PROBE_JUDGED s. A fault ends the phase (raised); the next phase
        starts a new controller (a world would recover it)."""
        controller = self.started()
        dt, start, target = self.dt, self.wrench.copy(), np.asarray(wrench, float)
        ramp, hold = self.rng.uniform(*PROBE_RAMP), self.rng.uniform(*PROBE_HOLD)
        steps, judged = int(round((ramp + hold) / dt)), int(round(PROBE_JUDGED / dt))
        total = np.zeros(6)
        try:
            for k in range(steps):
                self.wrench = start + (target - start) * min(1.0, (k + 1) * dt / ramp)
                twist = np.asarray(
                    controller.step(self.sensor.measure(self.wrench, dt), self.transform.copy(), params, dt), float
                )
                if twist.shape != (6,) or not np.all(np.isfinite(twist)):
                    raise ControllerFault(f"twist must be 6 finite numbers, got {twist!r}")
                self.transform[:3, 3] += twist[:3] * dt
                self.transform[:3, :3] = rotation_exp(twist[3:] * dt) @ self.transform[:3, :3]
                if k >= steps - judged:
                    total += twist
        except Exception:
            getattr(self.controller, "close", lambda: None)()
            self.controller = None
            raise
        return total / judged

    def started(self) -> Controller:
        """The stream's controller (a new one after a fault), reset as a world resets it (when the
        world is built and again when the trial resets the world), then started with the trial's
        force by its own start handler, as the world's start_lifting does."""
        if self.controller is None:
            self.controller = self.factory()
            self.controller.reset()
            self.controller.reset()
            self.params = LiftingParams()
            start = getattr(self.controller, "start", None)  # the world's start_lifting: the controller's handler
            if callable(start):  # none: not started, as a file's start() that does nothing (graded())
                start(self.params, TrialRules().force)
        return self.controller

    def close(self) -> None:
        getattr(self.controller, "close", lambda: None)()
        self.controller = None


def _cos(a: np.ndarray, b: np.ndarray) -> float:
    na, nb = np.linalg.norm(a), np.linalg.norm(b)
    return float(a @ b / (na * nb)) if na > 1e-12 and nb > 1e-12 else 0.0


def _fmt(v: np.ndarray) -> str:
    return "[" + ", ".join(f"{x:.3f}" for x in v) + "]"


def _split(twist: np.ndarray, rotation: np.ndarray) -> tuple[float, np.ndarray]:
    """(v_n, v_t): the linear twist along the plate normal n = R z, and across it (base frame)."""
    normal = rotation[:, 2]
    v_n = float(twist[:3] @ normal)
    return v_n, twist[:3] - v_n * normal


def _defines(controller: Controller, name: str) -> bool:
    """Whether the controller has its own handler `name` (a sandboxed file's: has_start/has_stop,
    as its child found them; the lab's handler stands in for a missing one in the live lab)."""
    return callable(getattr(controller, name, None)) and bool(getattr(controller, f"has_{name}", True))


def _probe_start_stop(stream: ProbeStream, draw: Draw) -> str:
    """The handlers alone, on a LiftingParams of their own (no stepping)."""
    controller, params = stream.started(), LiftingParams()
    force = round(draw.force, 1)
    missing = [f"{name}()" for name in ("start", "stop") if not _defines(controller, name)]
    if missing:  # no more than a start()/stop() left as the template's TODO scores
        return f"no {' and no '.join(missing)}: the start/stop services' handlers are part of the exercise"
    top = force + params.f_n_band  # the lab's band, read before the handler may change it
    controller.start(params, force)
    if not (np.isclose(params.f_n_min, force) and np.isclose(params.f_n_max, top) and params.running):
        return (
            f"after start({force:g}): f_n_min={params.f_n_min:g}, f_n_max={params.f_n_max:g}, running={params.running}; "
            f"expected {force:g}, {top:g}, True"
        )
    controller.stop(params)
    if (params.f_n_min, params.running) != (0.0, False):
        return f"after stop(): f_n_min={params.f_n_min:g}, running={params.running}; expected 0, False"
    return ""


def _probe_stopped(stream: ProbeStream, draw: Draw) -> str:
    twist = stream.phase([0, 0, draw.uniform(1.0, 5.0), 0, 0, 0], stream.stopped)
    return "" if np.linalg.norm(twist) < 1e-3 else f"stopped, yet commands {_fmt(twist)}"


def _normal_probe(low: float, high: float, sign: int) -> Callable:
    """f_n = f_n_min + U(low, high): move along sign * n (0: hold still) in the base frame."""

    def probe(stream: ProbeStream, draw: Draw) -> str:
        params = stream.params
        f_n = params.f_n_min + draw.uniform(low, high)
        twist = stream.phase([0, 0, f_n, 0, 0, 0], params)
        rotation = stream.rotation
        where = f"f_n = {f_n:.2f} N, band [{params.f_n_min:.2f}, {params.f_n_max:.2f}] N"
        if sign == 0:
            return "" if np.linalg.norm(twist[:3]) < 2e-3 else f"{where}: inside the band, yet moves {_fmt(twist[:3])}"
        direction = sign * rotation[:, 2]
        if np.linalg.norm(twist[:3]) < 1e-3:
            return f"{where}: no motion; expected along {'+' if sign > 0 else '-'}n = {_fmt(direction)} (base frame)"
        if _cos(twist[:3], direction) < 0.95:
            return f"{where}: moves along {_fmt(twist[:3])} (base frame); expected along {'+' if sign > 0 else '-'}n = {_fmt(direction)}"
        if np.linalg.norm(twist[:3]) > params.v_max + 1e-6 or np.linalg.norm(twist[3:]) > 0.05:
            return f"{where}: twist {_fmt(twist)} is beyond v_max or turns"
        return ""

    return probe


def _probe_band_end(stream: ProbeStream, draw: Draw) -> str:
    """f_n_max = f_n_min + f_n_band: 0.5 N below it still, 0.5 N above it release."""
    params = stream.params
    top = params.f_n_min + LiftingParams().f_n_band  # the lab's band, whatever the handler set
    for f_n, moving in ((top - 0.5, False), (top + 0.5, True)):
        v_n, _ = _split(stream.phase([0, 0, f_n, 0, 0, 0], params), stream.rotation)
        if moving and v_n > -1e-3:
            return f"f_n = {f_n:.2f} N > f_n_min + f_n_band = {params.f_n_max:.2f} N: v_n = {v_n:.4f} m/s, expected to release (< 0)"
        if not moving and abs(v_n) > 2e-3:
            return (
                f"f_n = {f_n:.2f} N < f_n_min + f_n_band = {params.f_n_max:.2f} N: v_n = {v_n:.4f} m/s, expected still"
            )
    return ""


def _tangential(stream: ProbeStream, draw: Draw, ratio_low: float, ratio_high: float, of_margin: bool):
    """A friction force |f_t| = ratio * (alpha) mu f_n along a random direction in the plate, f_n in
    the lower half of the band; returns (twist, f_t in the base frame, rotation, f_n, params, |f_t|)."""
    params = stream.params
    f_n = params.f_n_min + draw.uniform(0.5, 2.0)
    limit = (params.alpha if of_margin else 1.0) * params.mu * f_n
    ratio = draw.uniform(ratio_low, ratio_high)
    f_t_ee = draw.unit_in_plane() * ratio * limit
    twist = stream.phase([*f_t_ee[:2], f_n, 0, 0, 0], params)
    rotation = stream.rotation
    return twist, rotation @ f_t_ee, rotation, f_n, params, ratio * limit


def _probe_follow(stream: ProbeStream, draw: Draw) -> str:
    twist, f_t, rotation, f_n, params, size = _tangential(stream, draw, 1.3, 2.0, True)
    _, v_t = _split(twist, rotation)
    if np.linalg.norm(v_t) < 0.01 or _cos(v_t, -f_t) < 0.9:
        return (
            f"|f_t| = {size:.2f} N > alpha mu f_n = {params.alpha * params.mu * f_n:.2f} N: tangential motion {_fmt(v_t)}; "
            f"expected against f_t = {_fmt(f_t)} (base frame)"
        )
    return ""


def _probe_raise_grip(stream: ProbeStream, draw: Draw) -> str:
    twist, _, rotation, f_n, params, size = _tangential(stream, draw, 1.3, 2.0, True)
    v_n, _ = _split(twist, rotation)
    if v_n < 2e-3:
        return f"beyond the cone at f_n = {f_n:.2f} N (band up to {params.f_n_max:.2f} N): v_n = {v_n:.4f} m/s; expected to press toward f_n_max"
    return ""


def _probe_inside_cone(stream: ProbeStream, draw: Draw) -> str:
    twist, _, rotation, f_n, params, size = _tangential(stream, draw, 0.3, 0.75, True)
    _, v_t = _split(twist, rotation)
    if np.linalg.norm(v_t) > 2e-3:
        return f"|f_t| = {size:.2f} N inside alpha mu f_n = {params.alpha * params.mu * f_n:.2f} N, yet moves tangentially {_fmt(v_t)}"
    return ""


def _probe_margin(stream: ProbeStream, draw: Draw) -> str:
    """alpha mu f_n < |f_t| < mu f_n: the margin is left, the robot must already follow."""
    alpha = stream.params.alpha
    twist, f_t, rotation, f_n, params, size = _tangential(
        stream, draw, (1.0 + alpha) / 2.0 + 0.1 * (1 - alpha), 0.98, False
    )
    _, v_t = _split(twist, rotation)
    if np.linalg.norm(v_t) < 2e-3 or _cos(v_t, -f_t) < 0.9:
        return (
            f"|f_t| = {size:.2f} N between alpha mu f_n = {params.alpha * params.mu * f_n:.2f} N and mu f_n = {params.mu * f_n:.2f} N: "
            f"tangential motion {_fmt(v_t)}; expected against f_t (the margin alpha = {params.alpha:.2f} is left)"
        )
    return ""


def _moment_probe(about_normal: bool) -> Callable:
    def probe(stream: ProbeStream, draw: Draw) -> str:
        params = stream.params
        f_n = params.f_n_min + draw.uniform(1.0, 4.0)
        axis = np.array([0.0, 0.0, 1.0]) * np.sign(draw.uniform(-1, 1)) if about_normal else draw.unit_in_plane()
        moment = axis * draw.uniform(0.3, 0.8)
        twist = stream.phase([0, 0, f_n, *moment], params)
        expected = -(stream.rotation @ moment)
        if np.linalg.norm(twist[3:]) < 0.01 or _cos(twist[3:], expected) < 0.9:
            return f"moment {_fmt(moment)} Nm (EE frame) at the plate: turns {_fmt(twist[3:])}; expected to comply, along {_fmt(expected)} (base frame)"
        return ""

    return probe


PROBES = [
    ("start and stop set the band [force, force + 5] and running", _probe_start_stop),
    ("stopped: zero twist", _probe_stopped),
    ("below the band: press along +n", _normal_probe(-5.0, -2.0, +1)),
    ("below the band at another pose: +n in the base frame", _normal_probe(-5.0, -2.0, +1)),
    ("inside the band: hold still", _normal_probe(1.0, 4.0, 0)),
    ("above the band: release along -n", _normal_probe(7.0, 12.0, -1)),
    ("the band's upper end is f_n_min + 5 N", _probe_band_end),
    ("beyond the cone: follow against f_t", _probe_follow),
    ("beyond the cone: raise the grip toward f_n_max", _probe_raise_grip),
    ("inside the cone margin: no tangential motion", _probe_inside_cone),
    ("between the margin alpha mu f_n and the cone mu f_n: follow", _probe_margin),
    ("a moment in the plate's plane: comply", _moment_probe(False)),
    ("a moment about the plate's normal: comply", _moment_probe(True)),
]
# the order of the stream's phases (indices into PROBES): the second "below the band" comes after
# the moments have turned the pose; stopped and the start/stop handlers come last (a trial never
# stops: whatever the controller might make of a stop, nothing is judged after it)
STREAM_ORDER = (2, 4, 5, 6, 7, 8, 9, 10, 11, 12, 3, 1, 0)


def graded(factory: Callable[[], Controller]) -> Callable[[], Controller]:
    """The factory a grade uses: a student's file without start()/stop() gets no stand-in handlers
    (the live lab's), so it scores as one whose handlers do nothing: no more than the template's TODOs."""
    return replace(factory, stand_in=False) if isinstance(factory, PluginFactory) else factory


def probe_items(factory: Callable[[], Controller], seed: int = 0) -> list[Item]:
    """The probes' items (in PROBES order) from one stream; a fault costs the phase it broke."""
    reasons: dict[int, str] = {}
    stream = ProbeStream(graded(factory), seed)
    try:
        for index in STREAM_ORDER:
            try:
                stream.started()
                reasons[index] = PROBES[index][1](stream, Draw(seed, index))
            except Exception as exc:  # noqa: BLE001 - a fault or a file that cannot be loaded costs this item
                reasons[index] = str(exc)
    finally:
        stream.close()
    return [
        Item("probe", name, 0.0 if reasons[i] else PROBE_POINTS, PROBE_POINTS, reasons[i])
        for i, (name, _) in enumerate(PROBES)
    ]


# --- 2. the experiment and 3. robustness: trials judged by the world's state ----------------------------
def _run(
    trial: Trial, outputs, prefix: str = "", perturb: Callable[[Trial], None] | None = None
) -> tuple[TrialResult, LawWatch]:
    """Run a trial (perturb(trial) after every step), its stream watched for the SP law
    (sim/procedures/law_checks.py), recorded and plotted when asked (files prefixed `prefix`)."""
    observer, watch = None, LawWatch()
    if outputs is not None and outputs.wanted:
        observer = trial.observer = TrialObserver(trial, replace(outputs, prefix=prefix) if prefix else outputs)
    while trial.step():
        if perturb is not None:
            perturb(trial)
        watch.observe(trial.world)
    result = trial.result()
    if observer is not None:
        result.files = observer.finish(result)
    return result, watch


def _noisy_trial(controller, seed: int, outputs=None) -> tuple[TrialResult, LawWatch]:
    config = WorldConfig(sensor=SensorParams(force_noise_std=1.5, moment_noise_std=0.15))
    return _run(Trial(PARTICIPANTS["calm"], seed, controller, config=config), outputs, "robust_noise_")


def _pull_trial(controller, seed: int, outputs=None) -> tuple[TrialResult, LawWatch]:
    """2 s into the carry the person jerks the box 3 cm along the carry in 0.3 s (0.1 m/s on top of
    the path); later in the carry (where, drawn from the seed) the person stops: holds the box
    still 2 s, lets the robot take more of the weight, turns it (sim/procedures/situations.py)."""
    trial = Trial(PARTICIPANTS["calm"], seed, controller)
    human = trial.world.human
    direction = np.asarray(human.path_spec.carry_direction, float)
    pulled = [0]
    stop = MidCarryStop(np.random.default_rng([seed, 23]))

    def pull_then_stop(trial: Trial) -> None:
        if human.phase == "carrying" and human.phase_time >= 2.0 and pulled[0] < 300:
            human.start = human.start + direction * 0.0001
            pulled[0] += 1
        stop(trial)

    return _run(trial, outputs, "robust_pull_", pull_then_stop)


ROBUSTNESS = [
    ("three times the sensor noise (calm trial)", _noisy_trial),
    (
        "a sudden 3 cm pull while carrying, then a stop mid-carry: held still 2 s, more weight on the robot, "
        "the box turned (calm trial)",
        _pull_trial,
    ),
]


def _trial_detail(r: TrialResult) -> str:
    return (
        r.reason
        or f"carried in {r.duration:.1f} s, f_n {r.f_n_min:.1f}..{r.f_n_max:.1f} N, slip {r.slip * 1000:.1f} mm"
    )


def _judged(section: str, name: str, worth: float, result: TrialResult, watch: LawWatch) -> Item:
    """A trial's item: its points only when the box was carried AND the stream kept the SP law."""
    findings = watch.findings()
    detail = _trial_detail(result)
    if findings:  # each behaviour that was missing, where first
        detail += "; not SP: " + "; ".join(f"{BEHAVIOURS[f.behaviour]} was missing: {f.message}" for f in findings)
    return Item(section, name, worth if result.success and not findings else 0.0, worth, detail)


def trial_items(
    index: int,
    person: Participant,
    attempt: int,
    seed: int,
    factory: Callable[[], Controller],
    outputs: TrialOutputs | None = None,
) -> list[Item]:
    """The item of trial `index` of the experiment (a job of the battery: it runs in a worker)."""
    worth = TRIAL_POINTS if person.name in COUNTED_PARTICIPANTS else 0.0
    name = f"trial {index + 1}: {person.name} #{attempt}"
    trial = None
    try:
        trial = make_trial(index, person, attempt, seed, controller_factory=factory)
        return [_judged("experiment", name, worth, *_run(trial, outputs))]
    except Exception as exc:  # noqa: BLE001
        return [Item("experiment", name, 0.0, worth, f"not run: {exc}")]
    finally:
        getattr(getattr(trial, "controller", None), "close", lambda: None)()


def robustness_items(
    index: int, factory: Callable[[], Controller], seed: int, outputs: TrialOutputs | None = None
) -> list[Item]:
    """The item of robustness trial `index` (a job of the battery: it runs in a worker)."""
    name, run = ROBUSTNESS[index]
    controller = None
    try:
        controller = factory()
        return [
            _judged("robustness", name, ROBUSTNESS_POINTS, *run(controller, trial_seed(seed, 100 + index), outputs))
        ]
    except Exception as exc:  # noqa: BLE001
        return [Item("robustness", name, 0.0, ROBUSTNESS_POINTS, f"not run: {exc}")]
    finally:
        getattr(controller, "close", lambda: None)()


LOST = "not graded: "  # how the detail of an item whose worker process died begins


def lost_items(section: str, worths: tuple[tuple[str, float], ...], reason: str) -> list[Item]:
    """What a job whose worker process died stands in for: its items, each at 0 points, saying so."""
    return [Item(section, name, 0.0, worth, LOST + reason) for name, worth in worths]


@dataclass(frozen=True)
class Loaded:
    """Whether a submission loads, found where its battery will run (a worker of the pool or the
    cluster): `error` why the file cannot be loaded (its report's error), `refused` why this
    machine cannot run it sandboxed (no usable bubblewrap: the batch is refused), `reference` how
    it reached the lab's own controllers as it loaded (the sandbox's watch: not a submission)."""

    error: str = ""
    refused: str = ""
    reference: str = ""


def load_check(factory: Callable[[], Controller], sandboxed: bool = True) -> Loaded:
    """Start the controller once (in its sandbox) and close it (a job: it runs in a worker)."""
    if sandboxed and (reason := sandbox_unavailable()):
        return Loaded(refused=reason)
    try:
        controller = factory()  # loads in the sandbox: a file that cannot be loaded is reported
    except PluginError as exc:
        return Loaded(error=str(exc))
    getattr(controller, "close", lambda: None)()
    return Loaded(reference=getattr(controller, "reference", ""))


REFERENCE_ITEM = ("integrity", "the lab's reference controller")  # a flagged file's item (section, name)


def reference_items(reason: str) -> list[Item]:
    """What a file built on the lab's reference controllers gets when the course flags it instead of
    scoring it 0 (`--reference flag`): one item, not counted, that says so."""
    return [Item(*REFERENCE_ITEM, 0.0, 0.0, f"FLAGGED: {reason}")]


Items = Job[list[Item]]  # a job of the battery: its items


def probes_job(factory: Callable[[], Controller], seed: int, key: object = None) -> Items:
    worths = tuple((name, PROBE_POINTS) for name, _ in PROBES)
    return Job(key, probe_items, (factory, seed), len(PROBES), lost=partial(lost_items, "probe", worths))


def trial_job(
    index: int,
    person: Participant,
    attempt: int,
    seed: int,
    factory: Callable[[], Controller],
    outputs: TrialOutputs | None = None,
    key: object = None,
) -> Items:
    worth = TRIAL_POINTS if person.name in COUNTED_PARTICIPANTS else 0.0
    worths = ((f"trial {index + 1}: {person.name} #{attempt}", worth),)
    return Job(
        key,
        trial_items,
        (index, person, attempt, seed, factory, outputs),
        first=True,
        lost=partial(lost_items, "experiment", worths),
    )


def robustness_job(
    index: int,
    factory: Callable[[], Controller],
    seed: int,
    outputs: TrialOutputs | None = None,
    key: object = None,
) -> Items:
    worths = ((ROBUSTNESS[index][0], ROBUSTNESS_POINTS),)
    return Job(
        key,
        robustness_items,
        (index, factory, seed, outputs),
        first=True,
        lost=partial(lost_items, "robustness", worths),
    )


def battery(
    factory: Callable[[], Controller],
    seed: int = 0,
    sections: tuple[str, ...] = ("probe", "trial", "robustness"),
    trials: int = 9,
    outputs: TrialOutputs | None = None,
    key: object = None,
) -> list[Items]:
    """The jobs of a grade, in report order (the trials are handed out first: they are the long
    ones); outputs: a TrialOutputs (sim/recording/trial.py) to record and plot every trial;
    key: every job's (a batch's: the report it belongs to)."""
    jobs: list[Items] = []
    factory = graded(factory)
    if "probe" in sections:
        jobs.append(probes_job(factory, seed, key))
    if "trial" in sections:
        jobs += [
            trial_job(i, person, attempt, s, factory, outputs, key) for i, person, attempt, s in plan(trials, seed=seed)
        ]
    if "robustness" in sections:
        jobs += [robustness_job(i, factory, seed, outputs, key) for i in range(len(ROBUSTNESS))]
    return jobs


def run_items(
    jobs: Sequence[Items],
    workers: int = 1,
    on_item: Callable[[Item], None] | None = None,
    scheduler: str | None = None,
) -> list[Item]:
    """The items of `jobs` in their order (job.size each): here, in `workers` processes or on the
    Dask cluster at `scheduler`; on_item(item) as each ends."""

    def each(job: Items, items: list[Item]) -> None:
        for item in items:
            if on_item:
                on_item(item)

    results = run_jobs(jobs, workers, each, scheduler=scheduler)
    return [item for items in results for item in items or ()]


def grade(
    factory: Callable[[], Controller],
    name: str,
    seed: int = 0,
    jobs: int = 1,
    on_item: Callable[[Item], None] | None = None,
    sections: tuple[str, ...] = ("probe", "trial", "robustness"),
    trials: int = 9,
    outputs: TrialOutputs | None = None,
    scheduler: str | None = None,
) -> Report:
    report = new_report(name, seed)
    report.items = run_items(battery(factory, seed, sections, trials, outputs), jobs, on_item, scheduler)
    return report
