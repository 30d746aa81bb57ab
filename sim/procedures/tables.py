"""The experiment's results as text tables and data: Table 1 of the handout, a sweep, a comparison."""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from sim.procedures.experiment import Comparison, SweepRow
from sim.procedures.trial import TrialResult


def aggregate(results: list[TrialResult]) -> dict:
    """One participant's trials in one number each: successes, mean time of the successes (s),
    mean f_n min and max (N), mean max friction ratio, mean and max slip (m)."""
    ok = [r for r in results if r.success]
    return {
        "successes": len(ok),
        "trials": len(results),
        "mean_duration_success": float(np.mean([r.duration for r in ok])) if ok else None,
        "f_n_min": float(np.mean([r.f_n_min for r in results])),
        "f_n_max": float(np.mean([r.f_n_max for r in results])),
        "friction_ratio": float(np.mean([r.max_friction_ratio for r in results])),
        "slip_mean": float(np.mean([r.slip for r in results])),
        "slip_max": float(np.max([r.slip for r in results])),
    }


def by_participant(results: Iterable[TrialResult]) -> dict[str, list[TrialResult]]:
    out: dict[str, list[TrialResult]] = {}
    for r in results:
        out.setdefault(r.participant, []).append(r)
    return out


def sweep_json(rows: list[SweepRow]) -> dict:
    """The sweep as data (one point per row; per participant the aggregate; every trial)."""
    return {
        "parameters": list(rows[0].values) if rows else [],
        "points": [
            {
                "values": row.values,
                "participants": {p: aggregate(rs) for p, rs in by_participant(row.results).items()},
                "trials": [r.as_dict() for r in row.results],
            }
            for row in rows
        ],
    }


def format_sweep(rows: list[SweepRow], title: str = "") -> str:
    """One line per (point, participant): successes, time, slip, f_n range, friction ratio."""
    names = list(rows[0].values) if rows else []
    head = "".join(f"{n:>10} " for n in names)
    header = f"{head}{'participant':<11} {'ok':>4} {'time s':>7} {'slip mm mean/max':>17} {'f_n min..max':>13} {'|ft|/mu fn':>10}"
    lines = ([title] if title else []) + [header, "-" * len(header)]
    for row in rows:
        values = "".join(f"{v:>10g} " if isinstance(v, (int, float)) else f"{v!s:>10} " for v in row.values.values())
        for person, rs in by_participant(row.results).items():
            a = aggregate(rs)
            time_s = f"{a['mean_duration_success']:.1f}" if a["successes"] else "-"
            slip = f"{a['slip_mean'] * 1000:.1f}/{a['slip_max'] * 1000:.1f}"
            lines.append(
                f"{values}{person:<11} {a['successes']}/{a['trials']:<2} {time_s:>7} {slip:>17} "
                f"{a['f_n_min']:>6.1f}..{a['f_n_max']:<5.1f} {a['friction_ratio']:>10.2f}"
            )
    lines.append("-" * len(header))
    return "\n".join(line.rstrip() for line in lines)


def summary(results: list[TrialResult]) -> dict:
    ok = [r for r in results if r.success]
    return {
        "trials": len(results),
        "successes": len(ok),
        "success_rate": len(ok) / len(results) if results else 0.0,
        "mean_duration_success": float(np.mean([r.duration for r in ok])) if ok else None,
    }


def format_table(results: list[TrialResult], title: str = "") -> str:
    """The Table 1 of the handout as text; `title` (e.g. the parameters that differ from the
    defaults) goes above it."""
    header = f"{'#':>2}  {'participant':<11} {'try':>3}  {'success':<7} {'time s':>7} {'min f_n':>8} {'max f_n':>8} {'max |ft|/mu fn':>15} {'slip mm':>8}  reason"
    lines = ([title] if title else []) + [header, "-" * len(header)]
    for r in results:
        lines.append(
            f"{r.index + 1:>2}  {r.participant:<11} {r.attempt:>3}  {'yes' if r.success else 'NO':<7} {r.duration:>7.2f} "
            f"{r.f_n_min:>8.2f} {r.f_n_max:>8.2f} {r.max_friction_ratio:>15.2f} {r.slip * 1000:>8.1f}  {r.reason}"
        )
    s = summary(results)
    lines.append("-" * len(header))
    lines.append(f"success: {s['successes']}/{s['trials']}")
    return "\n".join(lines)


def format_comparison(results: Comparison, title: str = "") -> str:
    """Per participant, per controller: successes, mean time, f_n range, friction margin, slip."""
    names = list(results)
    header = f"{'participant':<11} " + " | ".join(f"{n:^44}" for n in names)
    sub = f"{'':<11} " + " | ".join(
        f"{'ok':>4} {'time s':>7} {'f_n min..max':>13} {'|ft|/mu fn':>10} {'slip mm':>7}" for _ in names
    )
    lines = ([title] if title else []) + [header, sub, "-" * len(sub)]
    people = list(dict.fromkeys(person for by in results.values() for person in by))
    for person in people:
        cells = []
        for name in names:
            rs = results[name].get(person, [])
            if not rs:  # not run (a cancelled comparison)
                cells.append(f"{'-':^44}")
                continue
            ok = [r for r in rs if r.success]
            time_s = f"{np.mean([r.duration for r in ok]):.1f}" if ok else "-"
            f_lo, f_hi = np.mean([r.f_n_min for r in rs]), np.mean([r.f_n_max for r in rs])
            cells.append(
                f"{len(ok)}/{len(rs):<2} {time_s:>7} {f_lo:>6.1f}..{f_hi:<5.1f} {np.mean([r.max_friction_ratio for r in rs]):>10.2f} "
                f"{np.mean([r.slip for r in rs]) * 1000:>7.1f}"
            )
        lines.append(f"{person:<11} " + " | ".join(cells))
    totals = []
    for name in names:
        rs = [r for by in results[name].values() for r in by]
        totals.append(f"{sum(r.success for r in rs)}/{len(rs)} succeeded")
    lines.append("-" * len(sub))
    lines.append(f"{'all':<11} " + " | ".join(f"{t:^44}" for t in totals))
    return "\n".join(line.rstrip() for line in lines)
