"""`hri-lab grade FILE.py`: the battery a student's controller is graded with (docs/grading-battery.md).

1. Probes (PROBE_POINTS each): the SP law's situations, as phases of ONE closed-loop stream that
   reaches the controller the way a trial does (app/grading/probe_stream.py).
2. The experiment (5 points per counted trial): the nine Table 1 trials (sim/procedures/trial.py)
   with the lab's default parameters; the participants in COUNTED_PARTICIPANTS count (all three: at
   the default margin alpha 0.5 the reference SP carries each of them). A trial's points need the
   box carried (the world's own state) AND its whole stream within the SP law, judged from the
   true contact and the controller's commands (app/grading/law_checks.py).
3. Robustness (10 points each, judged the same way): a calm trial with three times the sensor
   noise; a calm trial in which the person jerks the box 3 cm sideways in 0.3 s while carrying it,
   and later stops mid-carry, holds still 2 s, lets the robot take more of the weight and turns the
   box (app/grading/situations.py).
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

from sim.controllers.interface import Controller
from sim.controllers.plugin import PluginError
from sim.controllers.sandbox import sandbox_unavailable
from sim.person.participants import PARTICIPANTS, Participant
from sim.physics.sensor import SensorParams
from sim.procedures.experiment import plan
from sim.procedures.runner import Job, run_jobs
from sim.procedures.trial import Trial, TrialResult, make_trial, trial_seed
from sim.recording.trial import TrialObserver, TrialOutputs
from sim.world import WorldConfig

from app.grading.law_checks import BEHAVIOURS, LawWatch
from app.grading.probe_stream import PROBE_POINTS, PROBES, graded, probe_items
from app.grading.report import Item, Report
from app.grading.situations import MidCarryStop

PASS_MARK = 60.0  # % of all points
PROBE_PASS_MARK = 80.0  # % of the probes' points
# The one place that decides which trials count. All three participants count: measured with
# bench/margin_sweep.py (README, "The experiment"), SP at the default margin (alpha 0.5) carries the
# hasty participant too (3/3, slip <= 3.5 mm), and so does every alpha from 0.3 to 0.65; only the old
# default 0.8 dropped it (the margin's choice, not the method's). A submission that drops the hasty
# participant at the defaults follows too late, and that is the SP method's tangential step.
COUNTED_PARTICIPANTS = ("calm", "average", "hasty")
TRIAL_POINTS, ROBUSTNESS_POINTS = 5.0, 10.0


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


# --- 2. the experiment and 3. robustness: trials judged by the world's state ----------------------------
def _run(
    trial: Trial, outputs, prefix: str = "", perturb: Callable[[Trial], None] | None = None
) -> tuple[TrialResult, LawWatch]:
    """Run a trial (perturb(trial) after every step), its stream watched for the SP law
    (app/grading/law_checks.py), recorded and plotted when asked (files prefixed `prefix`)."""
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
    still 2 s, lets the robot take more of the weight, turns it (app/grading/situations.py)."""
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
    except Exception as exc:  # noqa: BLE001 - a trial that cannot run is an item "not run"
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
    except Exception as exc:  # noqa: BLE001 - a robustness trial that cannot run is an item "not run"
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
