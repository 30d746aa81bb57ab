"""A student's controller runs in a sandboxed process: what it does wrong costs its items with the
reason, never the grader; it cannot reach the grader, the world, the network or the files."""

import os
import re
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from sim.controllers.interface import ControllerFault, LiftingParams
from sim.controllers.plugin import PluginError, PluginFactory
from sim.controllers.sandbox import SandboxBudget, parent, pool, watch
from sim.person.participants import PARTICIPANTS
from sim.procedures.trial import Trial

from tests.waiting import process_gone, wait_for

CONTROLLERS = Path(__file__).resolve().parents[1] / "controllers"
FAULTS = CONTROLLERS / "faults.py"


def fault_of(name: str, budget: SandboxBudget = SandboxBudget(), steps: int = 3000) -> str:
    controller = PluginFactory(f"{FAULTS}:{name}", budget)()
    params = LiftingParams()
    controller.start(params, 10.0)
    try:
        with pytest.raises(ControllerFault) as fault:  # noqa: PT012 - the block sets up and triggers the refusal together
            for _ in range(steps):
                controller.step(np.array([0, 0, 4.0, 0, 0, 0]), np.eye(4), params, 1e-3)
    finally:
        controller.close()
    return str(fault.value)


@pytest.mark.parametrize(
    ("name", "budget", "reason"),
    [
        ("SleepsForever", SandboxBudget(step_timeout=1.0), "did not answer within 1 s (wall clock)"),
        ("Sleeps50ms", SandboxBudget(), "step sleeps or blocks"),
        ("StartsThread", SandboxBudget(), "started a thread or a process"),
        ("Forks", SandboxBudget(), "started a thread or a process"),
        ("MemoryBomb", SandboxBudget(memory_bytes=400 << 20), "MemoryError"),
        ("ExitsInStep", SandboxBudget(), "the controller's process exited with code 0"),
        ("SleepsNowAndThen", SandboxBudget(), "your step() took"),
        ("OpensFiles", SandboxBudget(), "Too many open files"),
    ],
)
def test_each_fault_stops_the_controller_with_its_reason(name, budget, reason):
    assert reason in fault_of(name, budget)


def test_a_sleeper_is_stopped_after_its_grace_with_the_wall_time_it_took():
    """2 s sleeps on 10 of every 250 steps stay within the count of sleeps (max_sleeps) and use no
    CPU: the wall time tells, counted as sleeping only when the child neither ran nor waited for a CPU."""
    budget = SandboxBudget()
    reason = fault_of("SleepsNowAndThen", budget)
    took = re.search(r"your step\(\) took ([\d.]+) s of wall time in (\d+) steps \(sleeping\?\): ([\d.]+) s", reason)
    assert took, reason
    wall, steps, sleeping = float(took[1]), int(took[2]), float(took[3])
    assert steps == 2  # its second 2-s sleep is beyond the grace (2 s) plus 2 ms of simulated time
    assert budget.sleep_grace + steps * 1e-3 < sleeping <= wall


def test_the_jails_writable_places_hold_what_the_budget_says():
    """100 files of 15 MiB into /tmp at import (1.5 GiB before): /tmp holds tmp_bytes; /dev/shm and
    every other place is read-only; memory files (memfd) hold file_bytes each, open_files of them."""
    budget = SandboxBudget()
    controller = PluginFactory(str(CONTROLLERS / "fills_disk.py"), budget)()
    try:
        in_tmp, elsewhere, in_memfds = controller.step(np.zeros(6), np.eye(4), LiftingParams(), 1e-3)[:3]
    finally:
        controller.close()
    mib = 1 << 20
    assert 0 < in_tmp <= budget.tmp_bytes / mib
    assert elsewhere == 0
    assert 0 < in_memfds <= budget.open_files * budget.file_bytes / mib


def test_a_thread_or_process_started_at_import_is_a_load_error():
    with pytest.raises(PluginError, match="started a thread or a process"):
        PluginFactory(str(CONTROLLERS / "thread_at_import.py"))()


def test_a_start_handler_is_held_to_the_parameters_ranges():
    """What start() writes is checked as a parameter set is (sim/ranges.py): refused, the start
    service fails with the reason and the lab's parameters stay as they were."""
    controller = PluginFactory(f"{FAULTS}:SetsHugeBand")()
    params = LiftingParams()
    before = repr(params)
    try:
        with pytest.raises(ControllerFault, match=r"Parameter \{f_n_min\} doesn't comply with floating point range"):
            controller.start(params, 10.0)
        assert repr(params) == before
        assert controller.step(np.zeros(6), np.eye(4), params, 1e-3).shape == (6,)  # refused, not stopped
    finally:
        controller.close()


@pytest.mark.parametrize(
    ("name", "reach"),
    [
        ("reference_sp.py", "it imports sim.controllers.sp"),  # the three lines: 130/130 PASS before
        ("copies_reference.py", "/sim/controllers/sp.py (sim.controllers.sp)"),  # its text read and run
        ("template_filled.py", ""),  # the template filled in: numpy only
    ],
)
def test_the_sandbox_sees_a_file_reach_for_the_labs_own_controllers(name, reach):
    controller = PluginFactory(str(CONTROLLERS / name))()
    try:
        assert controller.step(np.zeros(6), np.eye(4), LiftingParams(), 1e-3).shape == (6,)
    finally:
        controller.close()
    assert reach in controller.reference
    assert (controller.reference == "") == (reach == "")
    if reach:
        assert "is the lab's reference controller, not a submission" in controller.reference


def test_reaching_for_the_labs_controllers_after_loading_is_refused():
    refused = r"the lab's reference controllers are not a submission: your code (imports|reads) .*sim.controllers.sp"
    with pytest.raises(ControllerFault, match=refused):  # noqa: PT012 - the block sets up and triggers the refusal together
        controller = PluginFactory(str(CONTROLLERS / "imports_reference_late.py"))()
        try:
            controller.step(np.zeros(6), np.eye(4), LiftingParams(), 1e-3)
        finally:
            controller.close()


def test_exit_at_import_is_a_load_error():
    with pytest.raises(PluginError, match="failed: SystemExit: 0"):
        PluginFactory(str(CONTROLLERS / "exits_at_import.py"))()


def test_no_files_no_network_outside_the_sandbox():
    reason = fault_of("ReadsSecrets")
    assert "/etc/passwd: FileNotFoundError" in reason
    assert "root:" not in reason
    assert f"{FAULTS}: FileNotFoundError" in reason  # not even its own file: it arrives as text
    assert "connect: OSError" in reason  # no network (a socket it listens on is in its own namespace)


def test_patching_the_grader_in_the_child_changes_nothing_here():
    import app.grading.report as report_module

    passed = report_module.Report.__dict__["passed"]
    controller = PluginFactory(str(CONTROLLERS / "patches_grader.py"))()  # its class body patched the child's grader
    twist = controller.step(np.zeros(6), np.eye(4), LiftingParams(), 1e-3)
    controller.close()
    assert twist.tolist() == [0.0] * 6
    assert report_module.Report.__dict__["passed"] is passed
    empty = report_module.Report("x", "controller", 0)
    assert empty.passed is False
    assert empty.score == 0.0


def test_the_child_never_runs_at_the_loops_realtime_priority():
    """Spawned from a SCHED_FIFO thread (as the live loop is), the child runs SCHED_OTHER."""
    seen = {}

    def spawn_from_fifo() -> None:
        try:
            os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(1))
        except PermissionError:
            seen["skip"] = True
        controller = PluginFactory(str(CONTROLLERS / "reference_sp.py"))()
        seen["policies"] = [os.sched_getscheduler(pid) for pid in controller._tree()]
        controller.close()

    thread = threading.Thread(target=spawn_from_fifo)
    thread.start()
    thread.join()
    if seen.get("skip"):
        pytest.skip("this machine does not allow SCHED_FIFO (no CAP_SYS_NICE): nothing to reset")
    assert seen["policies"]
    assert all(p == os.SCHED_OTHER for p in seen["policies"])


def child_cpus(controller) -> set[int]:
    return {cpu for pid in controller._tree() for cpu in os.sched_getaffinity(pid)}


def in_a_thread(run) -> None:
    """run() in a thread of its own: the test run's CPUs stay as they were."""
    thread = threading.Thread(target=run)
    thread.start()
    thread.join()


def test_the_child_follows_the_parent_to_its_cpu(monkeypatch):
    """Parent and child take turns: the child is moved to whichever CPU the stepping thread is on
    (here set by the test), and the thread's own CPUs are given back when the child ends. (A pair
    that waits for its CPU is let go: never here, whatever else runs; the next test has that.)"""
    monkeypatch.setattr(parent, "SHARED_SHARE", float("inf"))
    cpus = sorted(os.sched_getaffinity(0))
    if len(cpus) < 2:
        pytest.skip("one CPU: nowhere else to follow the parent to")
    seen = {}

    def step_on(controller, cpu: int) -> set[int]:
        os.sched_setaffinity(0, {cpu})  # this thread only
        for _ in range(controller.budget.check_every):
            controller.step(np.zeros(6), np.eye(4), LiftingParams(), 1e-3)
        return child_cpus(controller)

    def run() -> None:
        controller = PluginFactory(str(CONTROLLERS / "reference_sp.py"))()
        try:
            seen["first"], seen["then"] = step_on(controller, cpus[-1]), step_on(controller, cpus[0])
        finally:
            controller.close()
        seen["after"] = os.sched_getaffinity(0)

    in_a_thread(run)
    assert seen == {"first": {cpus[-1]}, "then": {cpus[0]}, "after": {cpus[0]}}


def test_the_stepping_thread_and_the_child_share_one_cpu_and_are_let_go_when_it_does_other_work():
    """From the child's start the stepping thread and the child are on the CPU the thread runs on
    (a wake-up never goes to another CPU); a pair whose CPU does others' work (here: a busy process
    on every CPU) is let go to every CPU the thread had, and the thread has them back at the end."""
    cpus = sorted(os.sched_getaffinity(0))
    if len(cpus) < 2:
        pytest.skip("one CPU: nothing to pin to")
    seen = {}

    def run() -> None:
        controller = PluginFactory(str(CONTROLLERS / "reference_sp.py"))()
        busy = []
        try:
            controller.load()
            seen["pinned"] = (os.sched_getaffinity(0), child_cpus(controller))
            busy = [
                subprocess.Popen(["taskset", "-c", str(cpu), sys.executable, "-c", "while True: pass"]) for cpu in cpus
            ]
            end = time.monotonic() + 120  # a bound: the first look after SHARED_WINDOW lets go
            while controller._cpu is not None and time.monotonic() < end:
                controller.step(np.zeros(6), np.eye(4), LiftingParams(), 1e-3)
            seen["let go"] = (os.sched_getaffinity(0), child_cpus(controller))
        finally:
            for process in busy:
                process.kill()
                process.wait()
            controller.close()
        seen["after"] = os.sched_getaffinity(0)

    in_a_thread(run)
    (thread, child), everywhere = seen["pinned"], set(cpus)
    assert len(thread) == 1 and child == thread, seen
    assert seen["let go"] == (everywhere, everywhere), seen
    assert seen["after"] == everywhere


def test_the_childs_own_code_loads_no_robot_model():
    """The child's side of the sandbox (and the interface a student's file imports) loads neither
    pinocchio nor numba: every item of a grade starts a child, so its start-up is paid many times."""
    probe = (
        "import sys, sim.controllers.sandbox.child, sim.controllers.sandbox.zygote, sim.controllers.sandbox, "
        "sim.controllers.interface; "
        "print(sorted(m for m in ('pinocchio', 'numba', 'sim.robot.panda') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=60)
    assert out.stdout.strip() == "[]", out.stdout + out.stderr


def test_a_trial_is_judged_by_the_world_not_by_the_person_phase():
    """In-process (no sandbox), a controller that marks the person done gains nothing."""
    sys.path.insert(0, str(CONTROLLERS))
    from faults import ReachesTheWorld

    result = Trial(PARTICIPANTS["calm"], 1, ReachesTheWorld()).run()
    assert not result.success
    assert result.reason.startswith("not carried")


def test_grade_refuses_without_bubblewrap_unless_told(tmp_path):
    env = {**os.environ, "PATH": str(tmp_path)}  # no bwrap on PATH
    run = subprocess.run(
        [sys.executable, "-m", "app.cli", "grade", str(CONTROLLERS / "reference_sp.py")],
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
    )
    assert run.returncode == 2
    assert "refusing to run students' code without a sandbox" in run.stderr
    assert run.stdout == ""


def test_the_shared_slot_cannot_be_shrunk_under_the_parent():
    """The slot is sealed: the child's ftruncate fails in the child (unsealed, this process would
    die of SIGBUS at its next step)."""
    assert "PermissionError" in fault_of("ShrinksTheSlot")


def test_a_stale_answer_in_the_slot_is_not_taken_for_the_answer():
    """Each answer carries its request's number: a NaN twist under the previous number, with a
    wake-up, is passed over and the step's own answer is returned."""
    controller = PluginFactory(f"{FAULTS}:AnswersEarly")()
    reference = PluginFactory(str(CONTROLLERS / "reference_sp.py"))()
    params = LiftingParams()
    try:
        for controller_ in (controller, reference):
            controller_.start(params, 10.0)
        for _ in range(5):
            inputs = (np.array([0.3, -0.2, 4.0, 0.01, 0, 0]), np.eye(4), params, 1e-3)
            assert np.allclose(controller.step(*inputs), reference.step(*inputs))
    finally:
        controller.close()
        reference.close()


def test_a_file_built_on_the_lab_sp_loads_no_robot_model_in_its_child():
    """A student's file that subclasses the lab's SP (as the reference does) imports sim.controllers.sp
    in its child for every graded item: that loads no pinocchio (0.3 s of start-up each)."""
    probe = (
        "import sys, sim.controllers.sp; "
        "print(sorted(m for m in ('pinocchio', 'numba', 'sim.robot.panda') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=60)
    assert out.stdout.strip() == "[]", out.stdout + out.stderr


def _descendants() -> list[int]:
    """Every live process below this one (the multiprocessing resource tracker aside)."""
    from multiprocessing import resource_tracker

    own = {getattr(resource_tracker._resource_tracker, "_pid", None)}
    return [pid for pid in watch.process_tree(os.getpid())[1:] if pid not in own and not process_gone(pid)]


def test_nothing_one_item_leaves_reaches_the_next():
    """Every item is forked by the file's zygote before the file is imported, and the jail is
    cleared before each fork: a module global, a file in /tmp, a process, a System V segment left
    by one item are not there for the next; a POSIX queue cannot be made at all."""
    factory = PluginFactory(str(CONTROLLERS / "carries_state.py"))
    seen, jails = [], set()
    for _ in range(3):
        controller = factory()
        try:
            jails.add(id(controller._jail))
            seen.append(controller.step(np.zeros(6), np.eye(4), LiftingParams(), 1e-3).tolist())
            controller.reset()  # then the item leaves what it can for the next
        finally:
            controller.close()
    assert len(jails) == 1  # the same jail: the zygote forked each item
    assert seen == [[0.0] * 6] * 3


def test_a_crash_or_a_killed_zygote_costs_only_its_own_item(tmp_path):
    """An item that crashes, or kills the zygote that forked it, faults with its reason; the next
    item of the same class starts clean (from the same jail, or a new one) and steps."""
    crashes = tmp_path / "crashes.py"
    crashes.write_text(
        "import os, signal\nfrom sim.controllers.sp import SPController\n"
        "class CooperativeLifting(SPController):\n"
        "    def step(self, *args):\n"
        "        os.kill(os.getpid(), signal.SIGSEGV)\n"
    )
    kills = tmp_path / "kills_zygote.py"
    kills.write_text(
        "import os, signal\nfrom sim.controllers.sp import SPController\n"
        "class CooperativeLifting(SPController):\n"
        "    def step(self, *args):\n"
        "        os.kill(os.getppid(), signal.SIGKILL)\n"
        "        os.kill(os.getpid(), signal.SIGSEGV)\n"
    )
    reference = PluginFactory(str(CONTROLLERS / "reference_sp.py"))
    for broken, reason in ((crashes, "killed by SIGSEGV (a crash)"), (kills, "the controller's process")):
        controller = PluginFactory(str(broken))()
        with pytest.raises(ControllerFault, match=re.escape(reason)):
            controller.step(np.zeros(6), np.eye(4), LiftingParams(), 1e-3)
        controller.close()
        after = reference()
        try:
            params = LiftingParams()
            after.start(params, 10.0)
            twist = after.step(np.array([0, 0, 4.0, 0, 0, 0]), np.eye(4), params, 1e-3)
        finally:
            after.close()
        assert twist[2] > 0  # below the band: presses along +n


def test_no_jail_is_left_after_a_grade():
    """A grade's workers end their jails when they exit; in this process an idle jail ends
    IDLE_SECONDS after its last item: no zygote, no bubblewrap left either way."""
    from app.grading.battery import grade

    factory = PluginFactory(str(CONTROLLERS / "reference_sp.py"))
    before = set(_descendants())
    report = grade(factory, "reference", jobs=2, sections=("robustness",))
    assert report.score == 100.0
    wait_for(lambda: set(_descendants()) <= before)
    controller = factory()
    controller.close()
    assert pool._every  # idle in this process, for the next item
    wait_for(lambda: not pool._every and set(_descendants()) <= before)


def test_a_runaway_item_is_stopped_by_its_own_cpu_limit_and_the_next_starts_afresh(tmp_path):
    """RLIMIT_CPU is set in each forked child and counts from the fork: an item that spins is
    killed by it, its jail's zygote lives on, and the next item from the same jail steps (its
    clock did not inherit the spinner's CPU time)."""
    spins = tmp_path / "spins.py"
    spins.write_text(
        "from sim.controllers.sp import SPController\n"
        "class CooperativeLifting(SPController):\n"
        "    def step(self, *args):\n"
        "        while True:\n"
        "            pass\n"
    )
    budget = SandboxBudget(cpu_seconds=1, step_timeout=120.0)  # the CPU limit, not the wall clock, must end it
    runaway = PluginFactory(str(spins), budget)()
    jail = runaway._jail
    with pytest.raises(ControllerFault, match=r"SIGXCPU|SIGKILL"):
        runaway.step(np.zeros(6), np.eye(4), LiftingParams(), 1e-3)
    runaway.close()
    after = PluginFactory(str(CONTROLLERS / "reference_sp.py"), budget)()
    try:
        assert after._jail is jail  # the same zygote forked it
        params = LiftingParams()
        after.start(params, 10.0)
        assert after.step(np.array([0, 0, 4.0, 0, 0, 0]), np.eye(4), params, 1e-3)[2] > 0
    finally:
        after.close()
