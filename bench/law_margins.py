"""The figures the SP-law checks' thresholds come from (app/grading/law_checks.py): the
reference SP and the followers, each through the grader's watched trials (the counted trials and
the robustness situations), in-process, with each behaviour's worst figure per trial.

    .venv/bin/python -m bench.law_margins [--seed 0] [--trials 3] [--jobs 2] [--controllers sp,admittance,...]

Columns (worst over the trial, only where the situation arose; "-" = it never did):
  stick  mm the plate moved tangentially in 0.5 s with the friction inside the margin
  band   mm it moved along the normal in 0.5 s with f_n inside the band (and the friction inside)
  follow least cos(v_t, -f_t) kept 0.1 s with the friction beyond the margin (1 = against f_t)
  grip   least v_n (mm/s) kept 0.1 s beyond the margin below f_n_max (> 0 = raising the grip)
  moment least cos(w, -m_c) kept 0.1 s with a moment > 0.3 Nm at the plate (1 = complying)
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

CONTROLLERS = Path(__file__).resolve().parent.parent / "tests" / "controllers"
KINDS = {
    "sp": "reference_sp.py:CooperativeLifting",
    "template": "template_filled.py:CooperativeLifting",
    "admittance": "mutants.py:Admittance",
    "admittance_band": "followers.py:AdmittanceBand",
    "no_cone": "followers.py:NoCone",
    "moments_held": "mutants.py:MomentsHeld",
    "noise_free": "probe_detectors.py:NoiseFree",
    "still_pose": "probe_detectors.py:StillPose",
    "reset_pattern": "probe_detectors.py:ResetPattern",
    "elapsed_steps": "probe_detectors.py:ElapsedSteps",
    "ee_frame": "mutants.py:EEFrame",
}


def factory(name: str):
    if str(CONTROLLERS) not in sys.path:
        sys.path.insert(0, str(CONTROLLERS))
    module, cls = KINDS[name].split(":")
    return getattr(__import__(module[:-3]), cls)


def measure(job: tuple) -> tuple:
    """(controller, item, carried, reason, measures) of one watched trial."""
    from sim.procedures.trial import make_trial, trial_seed

    from app.grading import battery

    name, kind, index, person, attempt, seed, root_seed = job
    make = factory(name)
    if kind == "trial":
        result, watch = battery._run(make_trial(index, person, attempt, seed, controller_factory=make), None)
        label = f"trial {index + 1} {person.name}"
    else:
        _label_full, run = battery.ROBUSTNESS[index]
        result, watch = run(make(), trial_seed(root_seed, 100 + index), None)
        label = ["noise", "pull", "stop"][index]
    return name, label, result.success, result.reason, watch.measures()


def main() -> None:
    from sim.procedures.experiment import plan
    from sim.procedures.runner import worker_pool

    from app.grading.battery import ROBUSTNESS
    from app.grading.law_checks import BAND_MOVE, FOLLOW_COS, GRIP_SPEED, MOMENT_COS, STICK_MOVE

    parser = argparse.ArgumentParser()
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--trials", type=int, default=9, help="of the nine counted trials, every (9 / N)-th")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--controllers", default="sp,admittance,admittance_band,no_cone,elapsed_steps")
    args = parser.parse_args()
    names = args.controllers.split(",")
    counted = plan(9, seed=args.seed)[:: max(1, 9 // args.trials)]
    jobs = [(n, "trial", i, p, a, s, args.seed) for n in names for i, p, a, s in counted]
    jobs += [(n, "robustness", i, None, 0, 0, args.seed) for n in names for i in range(len(ROBUSTNESS))]
    with worker_pool(args.jobs) as pool:
        rows = list(pool.map(measure, jobs))

    def cell(value, scale=1.0, fmt="{:7.2f}"):
        return f"{'-':>7}" if value is None or math.isnan(value) else fmt.format(value * scale)

    print(f"seed {args.seed}")
    print(
        f"{'controller':<16} {'trial':<18} {'carried':<8} {'stick mm':>8} {'band mm':>8} {'follow':>7} {'grip mm/s':>9} {'moment':>7}"
    )
    worst: dict[str, dict[str, list[float]]] = {}
    for name, label, carried, reason, m in rows:
        print(
            f"{name:<16} {label:<18} {'yes' if carried else 'NO':<8} {cell(m['stick'][0], 1000):>8} {cell(m['band'][0], 1000):>8} "
            f"{cell(m['follow'][0]):>7} {cell(m['grip'][0], 1000):>9} {cell(m['moment'][0]):>7}  {reason[:50]}"
        )
        for key, (value, _) in m.items():
            if not math.isnan(value):
                worst.setdefault(name, {}).setdefault(key, []).append(value)
    print()
    print("the worst per controller over these trials, and the threshold (a trial breaks the law beyond it):")
    limits = {
        "stick": (max, STICK_MOVE * 1000, 1000, "mm, at most"),
        "band": (max, BAND_MOVE * 1000, 1000, "mm, at most"),
        "follow": (min, FOLLOW_COS, 1, "cos, at least"),
        "grip": (min, GRIP_SPEED * 1000, 1000, "mm/s, at least"),
        "moment": (min, MOMENT_COS, 1, "cos, at least"),
    }
    print(f"{'controller':<16} " + " ".join(f"{k:>9}" for k in limits))
    for name in names:
        cells = []
        for key, (pick, _, scale, _) in limits.items():
            values = worst.get(name, {}).get(key)
            cells.append(f"{pick(values) * scale:9.2f}" if values else f"{'-':>9}")
        print(f"{name:<16} " + " ".join(cells))
    print(f"{'threshold':<16} " + " ".join(f"{limit:9.2f}" for _, limit, _, _ in limits.values()))
    print("units: " + "; ".join(f"{k} {unit}" for k, (_, _, _, unit) in limits.items()))
    with open("/proc/loadavg") as handle:
        print(f"load average: {handle.read().split()[0]}")


if __name__ == "__main__":
    main()
