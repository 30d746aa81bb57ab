"""Sampling the simulated clock, which may go back: a reset of the world (the lifting world's or the
mobile one's, or a restarted simulation) starts its time again at 0 (docs/design.md, "Time may go
back").

Every throttled stream of the lab decides with `due` whether a sample may go out: HTTP topic streams,
rosbridge subscriptions at every throttle_rate, the camera's images and live recordings. So none of them goes silent after a reset until the simulated time climbs back past
where it was; each goes on within one period of the new trial's time."""

from __future__ import annotations

SLACK_S = 0.0005  # s: half a control period; a sample this close to its period counts as due


def due(last_s: float | None, now_s: float, period_s: float, slack_s: float = SLACK_S) -> bool:
    """Whether a sample at simulated time `now_s` (s) may go out, `last_s` being the time of the last
    one that went out (None: none has) and `period_s` the least gap between two (s). A time earlier
    than `last_s` belongs to a new trial (the world was reset): its first sample is due at once."""
    return last_s is None or now_s < last_s or now_s - last_s >= period_s - slack_s
