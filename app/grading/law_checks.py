"""The SP law judged inside a trial: from the world's TRUE contact figures at the plate and the
twist the controller commanded, over the trial's whole stream (docs/grading-battery.md).

A `LawWatch` is fed the world after every step (`observe(world)`: World's public attributes only)
and, at the end, says where the SP method's behaviours were missing (`findings()`):

  stick   inside the margin (|f_t| <= STICK_RATIO alpha mu f_n for LAG s): no tangential motion
          (the robot shares the load instead of sinking under it);
  follow  beyond it (|f_t| >= FOLLOW_RATIO alpha mu f_n for REACT s): move against f_t;
  grip    beyond it, below f_n_max - BAND_EDGE: press along +n (raise the grip toward f_n_max);
  band    inside the band [f_n_min + BAND_EDGE, f_n_max - BAND_EDGE], the friction inside the
          margin, for LAG s: no motion along the normal;
  moment  a moment at the plate centre above MOMENT for REACT s: turn with it (comply).

Only while the box is held by plate and palm alone (the person has let go of the grasp) and the
plate touches it (f_n >= CONTACT). f_t, f_n, the moment: the plate's contact on the box (world
frame), never the noisy F_ext; mu, alpha and the band: the trial's LiftingParams. The thresholds
are measured (bench/law_margins.py prints the figures they come from; the page gives the margins).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from sim.physics.contact import MOMENT_PATCH, NORMAL_FORCE, TANGENTIAL_FORCE

# --- thresholds (measured: bench/law_margins.py; docs/grading-battery.md states the margins) -----
LAG = 0.2  # s inside the margin / the band before motion is judged (filter, rate limit: the motion stops)
REACT = 0.05  # s beyond the margin / with a moment before the command's direction is judged
CONTACT = 1.0  # N, f_n below: no contact, nothing judged
STICK_RATIO = 0.8  # x alpha: the friction is inside the margin
FOLLOW_RATIO = 1.3  # x alpha: the friction is beyond it
BAND_EDGE = 1.0  # N inside each end of the band
MOMENT = 0.3  # Nm at the plate centre
WINDOW = 0.5  # s over which motion is summed
STICK_MOVE = 0.002  # m, most tangential motion in WINDOW inside the margin
BAND_MOVE = 0.002  # m, most normal motion in WINDOW inside the band
WRONG_TIME = 0.1  # s a wrong command must last to count (follow, grip, moment)
FOLLOW_COS = 0.5  # cos(v_t, -f_t) at least
FOLLOW_SPEED = 0.002  # m/s, |v_t| at least
GRIP_SPEED = 0.0002  # m/s, v_n at least
MOMENT_COS = 0.5  # cos(w, -m_c) at least
MOMENT_SPEED = 0.02  # rad/s, |w| at least

BEHAVIOURS = {
    "stick": "inside the friction margin: no tangential motion",
    "follow": "beyond the margin: follow against f_t",
    "grip": "beyond the margin: raise the grip toward f_n_max",
    "band": "inside the band: no normal motion",
    "moment": "a moment at the plate: comply",
}
COLUMNS = 18  # t, f_n, f_t (3), m_c (3), n (3), v (3), w (3), held by contact (1/0)


@dataclass
class Finding:
    behaviour: str  # a key of BEHAVIOURS
    time: float  # s of world time where it was first missing
    message: str


class LawWatch:
    """The stream of one trial (one row a step), judged at the end."""

    def __init__(self, capacity: int = 30000) -> None:
        self.rows = np.zeros((capacity, COLUMNS))
        self.count = 0
        self.params: Any = None  # the trial's LiftingParams, from its first step on

    def observe(self, world) -> None:
        """After a step: the plate's true contact, the plate normal and the command (world frame);
        only once the box is held by plate and palm alone (nothing is judged before)."""
        if not world.human.holding_by_contact:
            return
        if self.count == len(self.rows):
            self.rows = np.concatenate((self.rows, np.zeros_like(self.rows)))
        row = self.rows[self.count]
        plate = world.plate_out  # world.plate_state's numbers, read in place (every step of a trial)
        row[0] = world.time
        row[1] = plate[NORMAL_FORCE]
        row[2:5] = plate[TANGENTIAL_FORCE]
        row[5:8] = plate[MOMENT_PATCH]
        row[8:11] = world.arm.transform_ee_to_base[:3, 2]
        row[11:17] = world.twist_command
        row[17] = 1.0  # held by contact (kept: a stream's row says what it was judged under)
        self.count += 1
        self.params = world.params

    # --- the judgement ------------------------------------------------------------------------
    def figures(self) -> dict[str, np.ndarray]:
        """Per step: time, f_n, |f_t| / (alpha mu f_n), v_t, v_n, the moment, ... (world frame)."""
        r = self.rows[: self.count]
        p = self.params
        f_n, f_t, m_c, n, v, w = r[:, 1], r[:, 2:5], r[:, 5:8], r[:, 8:11], r[:, 11:14], r[:, 14:17]
        v_n = np.einsum("ij,ij->i", v, n)
        v_t = v - v_n[:, None] * n
        contact = (r[:, 17] > 0.5) & (f_n >= CONTACT)
        limit = p.alpha * p.mu * np.maximum(f_n, 1e-9)
        return {
            "t": r[:, 0],
            "f_n": f_n,
            "f_t": f_t,
            "ratio": np.linalg.norm(f_t, axis=1) / limit,
            "m_c": m_c,
            "v_n": v_n,
            "v_t": v_t,
            "w": w,
            "contact": contact,
        }

    def measures(self) -> dict[str, tuple[float, float]]:
        """The worst of each behaviour over the stream: (figure, world time); what the thresholds
        are measured on (bench/law_margins.py). stick/band: most motion (m) in WINDOW; follow:
        least cos(v_t, -f_t) over WRONG_TIME; grip: least v_n (m/s) over WRONG_TIME; moment: least
        cos(w, -m_c) over WRONG_TIME (nan: the situation never arose)."""
        s = self.figures()
        p, dt = self.params, _dt(s["t"])
        lag, react = int(round(LAG / dt)), int(round(REACT / dt))
        window, wrong = int(round(WINDOW / dt)), int(round(WRONG_TIME / dt))
        inside = s["contact"] & (s["ratio"] <= STICK_RATIO)
        beyond = s["contact"] & (s["ratio"] >= FOLLOW_RATIO)
        in_band = s["contact"] & (s["f_n"] >= p.f_n_min + BAND_EDGE) & (s["f_n"] <= p.f_n_max - BAND_EDGE) & inside
        moment = np.linalg.norm(s["m_c"], axis=1)
        turning = s["contact"] & (moment >= MOMENT)
        out = {}
        out["stick"] = _most_motion(np.linalg.norm(s["v_t"], axis=1) * dt, _lasted(inside, lag), window, s["t"])
        out["band"] = _most_motion(np.abs(s["v_n"]) * dt, _lasted(in_band, lag), window, s["t"])
        judged = _lasted(beyond, react)
        speed_t = np.linalg.norm(s["v_t"], axis=1)
        cos_follow = -np.einsum("ij,ij->i", s["v_t"], s["f_t"]) / np.maximum(
            speed_t * np.linalg.norm(s["f_t"], axis=1), 1e-12
        )
        cos_follow = np.where(speed_t >= FOLLOW_SPEED, cos_follow, -1.0)
        out["follow"] = _least_held(cos_follow, judged, wrong, s["t"])
        out["grip"] = _least_held(s["v_n"], judged & (s["f_n"] <= p.f_n_max - BAND_EDGE), wrong, s["t"])
        speed_w = np.linalg.norm(s["w"], axis=1)
        cos_moment = -np.einsum("ij,ij->i", s["w"], s["m_c"]) / np.maximum(speed_w * moment, 1e-12)
        cos_moment = np.where(speed_w >= MOMENT_SPEED, cos_moment, -1.0)
        out["moment"] = _least_held(cos_moment, _lasted(turning, react), wrong, s["t"])
        return out

    def findings(self) -> list[Finding]:
        """Where the stream broke the SP law ([] = nowhere), with the figures at that time."""
        if self.count == 0 or self.params is None:
            return []
        s, p, m = self.figures(), self.params, self.measures()
        found = []

        def at(time: float) -> int:  # the step at that time
            return min(int(np.searchsorted(s["t"], time - 1e-9)), len(s["t"]) - 1)

        def ratio(i: int) -> str:  # the friction at step i, as a share of mu f_n
            return f"{s['ratio'][i] * p.alpha:.2f} of mu f_n"

        # each behaviour: is its measure a breach, and the words for it at step i (time, measure value)
        rules: dict[str, tuple[Callable[[float], bool], Callable[[float, int, float], str]]] = {
            "stick": (
                lambda value: value > STICK_MOVE,
                lambda time, i, value: (
                    f"at {time:.1f} s the friction was {ratio(i)}, inside "
                    f"your margin alpha = {p.alpha:g}, yet the plate moved {value * 1000:.1f} mm along it in "
                    f"{WINDOW:g} s (at most {STICK_MOVE * 1000:g} mm)"
                ),
            ),
            "band": (
                lambda value: value > BAND_MOVE,
                lambda time, i, value: (
                    f"at {time:.1f} s f_n was {s['f_n'][i]:.1f} N, inside the band [{p.f_n_min:g}, "
                    f"{p.f_n_max:g}] N, yet the plate moved {value * 1000:.1f} mm along its normal in {WINDOW:g} s "
                    f"(at most {BAND_MOVE * 1000:g} mm)"
                ),
            ),
            "follow": (
                lambda value: value < FOLLOW_COS,
                lambda time, i, value: (
                    f"at {time:.1f} s the friction was {ratio(i)}, beyond "
                    f"your margin alpha = {p.alpha:g}, yet for {WRONG_TIME:g} s the plate did not follow against "
                    f"f_t (tangential speed {np.linalg.norm(s['v_t'][i]) * 1000:.1f} mm/s)"
                ),
            ),
            "grip": (
                lambda value: value < GRIP_SPEED,
                lambda time, i, value: (
                    f"at {time:.1f} s the friction was {ratio(i)}, beyond "
                    f"your margin, at f_n = {s['f_n'][i]:.1f} N < f_n_max = {p.f_n_max:g} N, yet for "
                    f"{WRONG_TIME:g} s the grip was not raised (v_n = {s['v_n'][i] * 1000:.1f} mm/s)"
                ),
            ),
            "moment": (
                lambda value: value < MOMENT_COS,
                lambda time, i, value: (
                    f"at {time:.1f} s the moment at the plate was "
                    f"{np.linalg.norm(s['m_c'][i]):.2f} Nm, yet for {WRONG_TIME:g} s the plate did not turn "
                    f"with it (|w| = {np.linalg.norm(s['w'][i]):.3f} rad/s)"
                ),
            ),
        }
        for behaviour, (broken, words) in rules.items():
            value, time = m[behaviour]
            if broken(value):
                found.append(Finding(behaviour, time, words(time, at(time), value)))
        return sorted(found, key=lambda f: f.time)


def _dt(t: np.ndarray) -> float:
    return float(t[1] - t[0]) if len(t) > 1 else 1e-3


def _lasted(condition: np.ndarray, steps: int) -> np.ndarray:
    """True where `condition` has held for the last `steps` steps (this one included)."""
    steps = max(steps, 1)
    held = np.concatenate(([0], np.cumsum(condition.astype(int))))
    out = np.zeros(len(condition), bool)
    out[steps - 1 :] = (held[steps:] - held[:-steps]) == steps
    return out


def _most_motion(motion: np.ndarray, judged: np.ndarray, window: int, t: np.ndarray) -> tuple[float, float]:
    """The most `motion` summed over `window` judged steps in a row: (sum, time of its window's start)."""
    moved = np.where(judged, motion, 0.0)
    total = np.concatenate(([0.0], np.cumsum(moved)))
    if len(moved) == 0:
        return 0.0, float("nan")
    width = min(window, len(moved))
    sums = total[width:] - total[:-width]
    # only windows wholly inside judged steps
    inside = np.concatenate(([0], np.cumsum(judged.astype(int))))
    whole = (inside[width:] - inside[:-width]) == width
    sums = np.where(whole, sums, 0.0)
    # a judged run shorter than a window counts whole
    if not whole.any() and judged.any():
        return float(moved.sum()), float(t[int(np.argmax(judged))])
    i = int(np.argmax(sums))
    return float(sums[i]), float(t[i])


def _least_held(value: np.ndarray, judged: np.ndarray, steps: int, t: np.ndarray) -> tuple[float, float]:
    """The least value kept for `steps` judged steps in a row (max over a sliding window, then min):
    (value, time the window began); nan when no window was judged."""
    n = len(value)
    if n < steps:
        return float("nan"), float("nan")
    v = np.where(judged, value, np.inf)
    windows = np.lib.stride_tricks.sliding_window_view(v, steps).max(axis=1)
    if not np.isfinite(windows).any():
        return float("nan"), float("nan")
    i = int(np.argmin(windows))
    return float(windows[i]), float(t[i])
