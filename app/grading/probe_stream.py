"""The probe stream of the controller grader (docs/grading-battery.md, "The probes"): the SP law's
situations as phases of ONE closed-loop stream that reaches the controller the way a trial does.

The probes (PROBE_POINTS each; app/grading/battery.py assembles them with the trials into the
battery): start/stop set the band; stopped -> zero; below the band -> +n (again at another pose:
the twist must be in the base frame); inside -> still; above -> -n; the band's upper end is
force + f_n_band; beyond the cone -> follow against f_t and raise the grip; inside the margin ->
no tangential motion; between the margin alpha mu f_n and the cone mu f_n -> follow; a moment in
the plate's plane and one about its normal -> comply. Wrenches, times, noise and start/stop's
force are drawn from the seed (a course's private seed gives numbers students never saw); a fault
costs the phase it broke.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np

from sim.controllers.interface import Controller, ControllerFault, LiftingParams
from sim.controllers.plugin import PluginFactory
from sim.monitor import TrialRules
from sim.physics.sensor import SensorParams, WrenchSensor
from sim.robot.panda import PandaModel
from sim.spatial import rotation_exp
from sim.world import WorldConfig

from app.grading.report import Item

PROBE_POINTS = 5.0  # a probe's worth

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
    twist, _, rotation, f_n, params, _size = _tangential(stream, draw, 1.3, 2.0, True)
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
