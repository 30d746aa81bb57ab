"""The lab's actions (docs/design.md, "Actions"), one declaration each."""

import multiprocessing
from multiprocessing import resource_tracker
from multiprocessing.context import BaseContext
from pathlib import Path
from typing import Annotated

from pydantic import BeforeValidator, Field

from sim.controllers.builtin import BUILTIN
from sim.person.participants import PARTICIPANTS
from sim.procedures.experiment import COMPARISON_PARTICIPANTS, ComparedTrial, run_comparison
from sim.procedures.experiment import run_experiment as run_trials
from sim.procedures.runner import worker_pool
from sim.procedures.tables import format_comparison, format_table
from sim.procedures.trial import TrialResult
from sim.recording.trial import TrialOutputs

from app.lab import commands as cmd
from app.lab import overrides
from app.ros.actions import Action, GoalFailure, GoalHandle
from app.ros.messages import (
    Bool,
    Empty,
    Float64,
    Int32,
    Int32Array,
    Int64,
    RosMessage,
    RosType,
    String,
    StringArray,
    integral,
)
from app.ros.params import ParameterRefused

# `set`: parameters for every trial of the goal, NAME=VALUE separated by spaces; the schema says
# the syntax, the parameter server's rules (declared, type, range) reject a goal up front (409)
SET_PATTERN = r"^\s*([A-Za-z_][A-Za-z0-9_/]*=\S+(\s+|$))*$"
SetField = Annotated[
    str,
    Field(max_length=2000, alias="set", pattern=SET_PATTERN),
    RosType("string", "parameters for every trial, e.g. 'alpha=0.5 k_t=0.2'"),
]


def overrides_valid(lab, goal) -> str | None:
    """Why the goal's `set` is refused (the parameter server's message), or None."""
    try:
        overrides.parse_set(goal.set_)
    except ParameterRefused as refused:
        return f"set: {refused}"
    return None


def _names(choices) -> str:
    """A pattern for a comma-separated list of some of `choices`."""
    one = "(" + "|".join(choices) + ")"
    return f"^{one}(,{one})*$"


# --- /count: the seed's counting action ------------------------------------------------------
class CountGoal(RosMessage):
    count: Annotated[int, Field(ge=0, le=3600), BeforeValidator(integral), RosType("int32")]


class CountResult(RosMessage):
    final_count: Int32


class CountFeedback(RosMessage):
    current_number: Int32


def count(lab, goal: CountGoal, handle: GoalHandle) -> CountResult:
    """Count 1, 2, ..., goal.count, one number a second; a cancel stops at the last number."""
    current = 0
    while current < goal.count:
        if handle.wait(1.0):
            break
        current += 1
        handle.feedback(CountFeedback(current_number=current))
    return CountResult(final_count=current)


# --- /move_to_start ----------------------------------------------------------------------------
class MoveResult(RosMessage):
    success: Bool
    message: String


class MoveFeedback(RosMessage):
    progress: Float64  # 0..1


def robot_free(lab, goal: Empty) -> str | None:
    """Why the robot cannot move to the start pose now (the goal is refused up front), or None."""
    s = lab.snapshot()
    if s.lifting.running:
        return "cooperative lifting is running: call /stop_cooperative_lifting first"
    if s.error:
        return f"the robot is in error ({s.error}): call /error_recovery first"
    return None


def move_to_start(lab, goal: Empty, handle: GoalHandle) -> MoveResult:
    """Drive the robot to the start pose with a smooth joint motion (lifting must be stopped)."""
    try:
        duration = lab.call(cmd.begin_move_to_start)
    except RuntimeError as exc:  # lifting started between the precondition and the start
        raise GoalFailure(str(exc)) from None
    while True:
        if handle.wait(0.1):
            lab.call(cmd.stop_motion)
            return MoveResult(success=False, message="canceled: the robot braked to rest")
        progress, moving, error = lab.call(cmd.motion_progress)
        if error:
            raise GoalFailure(f"robot reflex: {error}")
        handle.feedback(MoveFeedback(progress=progress))
        if not moving:
            return MoveResult(success=True, message=f"at the start pose ({duration:.1f} s motion)")


# --- /run_experiment ---------------------------------------------------------------------------
class ExperimentGoal(RosMessage):
    trials: Annotated[int, Field(ge=1, le=27), BeforeValidator(integral), RosType("int32")] = 9
    participant: Annotated[str, Field(pattern="^(|" + "|".join(PARTICIPANTS) + ")$"), RosType("string")] = ""
    seed: Int64 = 0
    plots: Annotated[bool, RosType("bool", "a figure of every trial and a summary (result: figures)")] = False
    set_: SetField = ""


class ExperimentResult(RosMessage):
    trials: Int32
    successes: Int32
    table: String
    figures: StringArray = []  # URLs (GET /figures/RUN/NAME.png), the summary first  # noqa: RUF012 - a pydantic field's or a test double's default, copied or shared on purpose


def _figures_of(lab, handle: GoalHandle):
    """Where a goal's figures go (lab.figures_dir/<goal id>) as TrialOutputs, and their URLs."""
    folder = Path(lab.figures_dir) / handle.id
    folder.mkdir(parents=True, exist_ok=True)
    return TrialOutputs(plots_dir=str(folder)), folder


def _summary_figure(results: dict, folder: Path) -> None:
    with worker_pool(1, spawn_context()) as pool:  # matplotlib in a worker, off the server
        pool.submit(save_summary_figure, results, str(folder)).result()


def save_summary_figure(results: dict, folder: str) -> dict:
    """In a worker process (matplotlib is never imported by the server)."""
    from sim.recording.figures import save_summary_figure as save

    return save(results, folder)


def _figure_urls(folder: Path) -> list[str]:
    names = sorted(p.name for p in folder.glob("*.png"))
    names.sort(key=lambda n: n != "summary.png")
    return [f"/figures/{folder.name}/{n}" for n in names]


class ExperimentFeedback(RosMessage):
    trial: Int32
    of: Int32
    participant: String
    success: Bool
    duration: Float64
    reason: String


SPAWN = multiprocessing.get_context("spawn")  # worker processes never fork the server's threads


def spawn_context() -> BaseContext:
    """SPAWN, its resource tracker running first: each semaphore a pool creates is then registered
    with a live tracker at once, which unlinks it should the server be killed. Started lazily,
    the tracker's start-up came between the pool's first semaphore and its registration, and a
    server killed then left a named semaphore in /dev/shm (4 of 16 kills timed as the tracker
    appeared, tests/e2e/test_workers.py's old wait; none of 16 since)."""
    resource_tracker.ensure_running()
    return SPAWN


def run_experiment(lab, goal: ExperimentGoal, handle: GoalHandle) -> ExperimentResult:
    """The Table 1 trials headless, each on its own world in a worker process (the live robot and
    its 1 kHz loop are untouched); a cancel stops after the running trial."""
    found = overrides.parse_set(goal.set_)
    outputs, folder = _figures_of(lab, handle) if goal.plots else (None, None)
    done = []

    def feedback(result: TrialResult) -> None:
        done.append(result)
        handle.feedback(
            ExperimentFeedback(
                trial=len(done),
                of=goal.trials,
                participant=result.participant,
                success=result.success,
                duration=result.duration,
                reason=result.reason,
            )
        )

    results = run_trials(
        goal.trials,
        goal.participant or None,
        goal.seed,
        on_result=feedback,
        setup=overrides.setup_of(found),
        cancelled=lambda: handle.cancel_requested,
        mp_context=spawn_context(),
        outputs=outputs,
    )
    if folder is not None:
        _summary_figure({"sp": results}, folder)
    return ExperimentResult(
        trials=len(results),
        successes=sum(r.success for r in results),
        table=format_table(results, overrides.describe(found)),
        figures=_figure_urls(folder) if folder is not None else [],
    )


# --- /compare_controllers ----------------------------------------------------------------------
class CompareGoal(RosMessage):
    controllers: Annotated[str, Field(pattern=_names(BUILTIN)), RosType("string", "comma-separated, e.g. sp,patch")] = (
        "sp,patch"
    )
    trials: Annotated[int, Field(ge=1, le=5), BeforeValidator(integral), RosType("int32", "tries per participant")] = 1
    participants: Annotated[
        str,
        Field(pattern="^$|" + _names(PARTICIPANTS)),
        RosType("string", "comma-separated; '' = " + ",".join(COMPARISON_PARTICIPANTS)),
    ] = ""
    seed: Int64 = 0
    plots: Annotated[bool, RosType("bool", "a figure of every trial and a summary (result: figures)")] = False
    set_: SetField = ""


class CompareResult(RosMessage):
    controllers: StringArray
    successes: Int32Array  # per controller
    trials: Int32Array  # per controller
    table: String
    figures: StringArray = []  # URLs (GET /figures/RUN/NAME.png), the summary first  # noqa: RUF012 - a pydantic field's or a test double's default, copied or shared on purpose


class CompareFeedback(RosMessage):
    controller: String
    participant: String
    trial: Int32
    of: Int32
    success: Bool
    duration: Float64
    reason: String


def compare_controllers(lab, goal: CompareGoal, handle: GoalHandle) -> CompareResult:
    """The same participants and seeds with each controller (headless worlds in a worker process;
    the live robot is untouched); feedback per trial; a cancel stops after the running trial."""
    names = goal.controllers.split(",")
    people = goal.participants.split(",") if goal.participants else None
    total = len(names) * goal.trials * len(people or COMPARISON_PARTICIPANTS)
    done = []

    def feedback(item: ComparedTrial, result: TrialResult) -> None:
        done.append(result)
        handle.feedback(
            CompareFeedback(
                controller=item.controller,
                participant=result.participant,
                trial=len(done),
                of=total,
                success=result.success,
                duration=result.duration,
                reason=result.reason,
            )
        )

    found = overrides.parse_set(goal.set_)
    outputs, folder = _figures_of(lab, handle) if goal.plots else (None, None)
    results = run_comparison(
        names,
        goal.trials,
        people,
        goal.seed,
        on_result=feedback,
        setup=overrides.setup_of(found),
        cancelled=lambda: handle.cancel_requested,
        mp_context=spawn_context(),
        outputs=outputs,
    )
    runs = [[r for rs in results[name].values() for r in rs] for name in names]
    if folder is not None:
        _summary_figure(dict(zip(names, runs)), folder)
    return CompareResult(
        controllers=names,
        successes=[sum(r.success for r in rs) for rs in runs],
        trials=[len(rs) for rs in runs],
        table=format_comparison(results, overrides.describe(found)),
        figures=_figure_urls(folder) if folder is not None else [],
    )


ACTIONS = [
    Action(
        "/count",
        "hri_lab/Count",
        CountGoal,
        CountResult,
        CountFeedback,
        count,
        "Count up to `count`, one number a second (the seed's action).",
    ),
    Action(
        "/move_to_start",
        "hri_lab/MoveToStart",
        Empty,
        MoveResult,
        MoveFeedback,
        move_to_start,
        "Move the robot to the start (side) pose with a smooth joint motion; cancel brakes it. "
        "Refused (409) while lifting runs or the robot is in error.",
        precondition=robot_free,
    ),
    Action(
        "/run_experiment",
        "hri_lab/RunExperiment",
        ExperimentGoal,
        ExperimentResult,
        ExperimentFeedback,
        run_experiment,
        "Run the lab's Table 1 trials headless (own worlds, worker process); feedback per trial. "
        "A `set` the parameter server refuses rejects the goal (409, its message).",
        precondition=overrides_valid,
    ),
    Action(
        "/compare_controllers",
        "hri_lab/CompareControllers",
        CompareGoal,
        CompareResult,
        CompareFeedback,
        compare_controllers,
        "Run the same participants and seeds with each controller (sp, patch) and compare them side by side. "
        "A `set` the parameter server refuses rejects the goal (409, its message).",
        precondition=overrides_valid,
    ),
]
