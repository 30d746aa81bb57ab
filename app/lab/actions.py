"""The lab's actions (DESIGN.md section 7), one declaration each."""
import multiprocessing
import time
from concurrent.futures import ProcessPoolExecutor
from typing import Annotated

from pydantic import Field

from sim.procedures.experiment import (
    COMPARISON_PARTICIPANTS,
    ComparedTrial,
    TrialResult,
    format_comparison,
    format_table,
    plan,
    run_comparison,
    run_trial,
)
from sim.person.human import PARTICIPANTS
from sim.controllers.plugin import BUILTIN
from sim.world import World

from app.lab import commands as cmd
from app.ros.actions import Action, GoalFailure, GoalHandle
from app.ros.messages import Bool, Empty, Float64, Int32, Int64, RosMessage, RosType, String, int32_array, string_array


def _names(choices) -> str:
    """A pattern for a comma-separated list of some of `choices`."""
    one = "(" + "|".join(choices) + ")"
    return f"^{one}(,{one})*$"


# --- /count: the seed's counting action ------------------------------------------------------
class CountGoal(RosMessage):
    count: Annotated[int, Field(ge=0, le=3600), RosType("int32")]


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
            lab.call(World.stop_motion)
            return MoveResult(success=False, message="canceled: the robot braked to rest")
        progress, moving, error = lab.call(cmd.motion_progress)
        if error:
            raise GoalFailure(f"robot reflex: {error}")
        handle.feedback(MoveFeedback(progress=progress))
        if not moving:
            return MoveResult(success=True, message=f"at the start pose ({duration:.1f} s motion)")


# --- /run_experiment ---------------------------------------------------------------------------
class ExperimentGoal(RosMessage):
    trials: Annotated[int, Field(ge=1, le=27), RosType("int32")] = 9
    participant: Annotated[str, Field(pattern="^(|" + "|".join(PARTICIPANTS) + ")$"), RosType("string")] = ""
    seed: Int64 = 0


class ExperimentResult(RosMessage):
    trials: Int32
    successes: Int32
    table: String


class ExperimentFeedback(RosMessage):
    trial: Int32
    of: Int32
    participant: String
    success: Bool
    duration: Float64
    reason: String


def run_experiment(lab, goal: ExperimentGoal, handle: GoalHandle) -> ExperimentResult:
    """The Table 1 trials headless, each on its own world in a worker process (the live robot and
    its 1 kHz loop are untouched); a cancel stops after the running trial."""
    work = plan(goal.trials, goal.participant or None, goal.seed)
    results = []
    context = multiprocessing.get_context("spawn")  # never fork the server's threads
    with ProcessPoolExecutor(max_workers=1, mp_context=context) as pool:
        for index, person, attempt, seed in work:
            future = pool.submit(run_trial, index, person, attempt, seed)
            while not future.done():
                time.sleep(0.05)
            result = future.result()
            results.append(result)
            handle.feedback(ExperimentFeedback(
                trial=index + 1, of=len(work), participant=result.participant, success=result.success,
                duration=result.duration, reason=result.reason,
            ))
            if handle.cancel_requested:
                break
    return ExperimentResult(trials=len(results), successes=sum(r.success for r in results), table=format_table(results))


# --- /compare_controllers ----------------------------------------------------------------------
class CompareGoal(RosMessage):
    controllers: Annotated[str, Field(pattern=_names(BUILTIN)), RosType("string", "comma-separated, e.g. sp,patch")] = "sp,patch"
    trials: Annotated[int, Field(ge=1, le=5), RosType("int32", "tries per participant")] = 1
    participants: Annotated[str, Field(pattern="^$|" + _names(PARTICIPANTS)),
                            RosType("string", "comma-separated; '' = " + ",".join(COMPARISON_PARTICIPANTS))] = ""
    seed: Int64 = 0


class CompareResult(RosMessage):
    controllers: string_array()
    successes: int32_array()  # per controller
    trials: int32_array()  # per controller
    table: String


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
        handle.feedback(CompareFeedback(controller=item.controller, participant=result.participant, trial=len(done), of=total,
                                        success=result.success, duration=result.duration, reason=result.reason))

    results = run_comparison(names, goal.trials, people, goal.seed, on_result=feedback,
                             cancelled=lambda: handle.cancel_requested, mp_context=multiprocessing.get_context("spawn"))
    runs = [[r for rs in results[name].values() for r in rs] for name in names]
    return CompareResult(controllers=names, successes=[sum(r.success for r in rs) for rs in runs],
                         trials=[len(rs) for rs in runs], table=format_comparison(results))


ACTIONS = [
    Action("/count", "hri_lab/Count", CountGoal, CountResult, CountFeedback, count,
           "Count up to `count`, one number a second (the seed's action)."),
    Action("/move_to_start", "hri_lab/MoveToStart", Empty, MoveResult, MoveFeedback, move_to_start,
           "Move the robot to the start (side) pose with a smooth joint motion; cancel brakes it. "
           "Refused (409) while lifting runs or the robot is in error.", precondition=robot_free),
    Action("/run_experiment", "hri_lab/RunExperiment", ExperimentGoal, ExperimentResult, ExperimentFeedback, run_experiment,
           "Run the lab's Table 1 trials headless (own worlds, worker process); feedback per trial."),
    Action("/compare_controllers", "hri_lab/CompareControllers", CompareGoal, CompareResult, CompareFeedback,
           compare_controllers,
           "Run the same participants and seeds with each controller (sp, patch) and compare them side by side."),
]
