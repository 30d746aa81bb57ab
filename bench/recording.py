"""Recording's cost and size, and the time to write a figure.

    .venv/bin/python -m bench.recording [--seconds 6] [--repeats 3]

1. The 1 kHz loop's lateness p99 (/health, the last 5000 ticks) of a live server with lifting
   running, without and with a live recording (alternating, `repeats` times each).
2. Bytes per second of recording: the live file / wall time; a calm trial's file / simulated time.
3. Time to write one trial's figure (PNG + SVG) of a calm trial (~20 s, 200 Hz signals).
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import httpx

from app.serving.launch import running_server


def loop_cost(seconds: float, repeats: int, folder: Path) -> None:
    with running_server("--view", "none", "--output-dir", str(folder)) as server:
        url = server.url
        httpx.post(f"{url}/services/start_cooperative_lifting", json={"force": 10})
        time.sleep(2.0)
        without, with_, rates = [], [], []
        for i in range(repeats):
            time.sleep(seconds)
            without.append(httpx.get(f"{url}/health").json()["lateness_p99_ms"])
            httpx.post(f"{url}/services/start_recording", json={"name": f"bench{i}"})
            started = time.monotonic()
            time.sleep(seconds)
            with_.append(httpx.get(f"{url}/health").json()["lateness_p99_ms"])
            stopped = httpx.post(f"{url}/services/stop_recording", json={}).json()
            rates.append(stopped["bytes"] / (time.monotonic() - started))
    print(
        f"1 kHz loop lateness p99 ({repeats} x {seconds:g} s, lifting running): without recording "
        f"{statistics.median(without):.3f} ms (runs {', '.join(f'{x:.2f}' for x in without)}), "
        f"with {statistics.median(with_):.3f} ms (runs {', '.join(f'{x:.2f}' for x in with_)})"
    )
    print(f"live recording: {statistics.median(rates) / 1024:.0f} KiB/s (topics 100 Hz, /tf + /scene 25 Hz, zstd)")


def trial_cost(folder: Path) -> None:
    from sim.procedures.experiment import plan
    from sim.procedures.trial import run_trial
    from sim.recording.figures import save_trial_figure
    from sim.recording.trial import TrialOutputs

    item = plan(1, "calm", 0)[0]
    result = run_trial(*item, outputs=TrialOutputs(record_dir=str(folder)))
    size = Path(result.files["recording"]).stat().st_size
    print(
        f"trial recording: {size / 1024:.0f} KiB for {result.duration:.1f} s simulated = "
        f"{size / result.duration / 1024:.0f} KiB/s"
    )
    from sim.procedures.trial import Trial
    from sim.recording.trial import TrialObserver

    index, person, attempt, seed = item
    trial = Trial(person, seed, index=index, attempt=attempt)
    trial.observer = TrialObserver(trial, TrialOutputs())
    result = trial.run()
    times = []
    for i in range(3):
        started = time.perf_counter()
        save_trial_figure(trial.observer.trace, result, folder / f"figure{i}")
        times.append(time.perf_counter() - started)
    print(
        f"one trial's figure (PNG + SVG, {len(trial.observer.trace.time)} samples): "
        f"{statistics.median(times):.2f} s median of 3 (first {times[0]:.2f} s)"
    )


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--seconds", type=float, default=6.0)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        trial_cost(Path(tmp))
        loop_cost(args.seconds, args.repeats, Path(tmp))


if __name__ == "__main__":
    main()
