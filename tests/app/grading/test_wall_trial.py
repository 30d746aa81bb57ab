"""app/grading/wall_trial.py's verdict (`judge`) without a world or a program: the monitor's verdict
is the trial's; a program that ends, stays silent or falls behind is said so (the trial with a
world and a program: tests/e2e/test_grade_wall.py)."""

import threading
import time
from collections import deque
from types import SimpleNamespace

import pytest

from sim.mobile.monitor import WallState
from sim.mobile.world import MobileConfig

from app.grading import wall_trial
from app.grading.wall import TrialOutcome
from app.grading.wall_trial import Program, judge


class Lab:
    """The trial's world as judge reads it: the monitor's state, one snapshot at a time."""

    def __init__(self, *states: WallState) -> None:
        self.states = list(states)

    def snapshot(self):
        state = self.states.pop(0) if len(self.states) > 1 else self.states[0]
        return SimpleNamespace(wall=state)


def program(code: int | None = None, lines=()) -> Program:
    """A program that is still running (code None) or ended with `code`, its last lines kept."""
    found = Program.__new__(Program)  # not started: judge reads only its process's status and lines
    found.proc = SimpleNamespace(poll=lambda: code, returncode=code)
    found.lines = deque(lines, maxlen=wall_trial.OUTPUT_LINES)
    found.group = None  # no cgroup: nothing it ran into
    found._reader = threading.Thread(target=lambda: None)  # its output read to the end
    found._reader.start()
    return found


def test_the_monitors_verdict_is_the_trials():
    lab = Lab(WallState(elapsed=1.0), WallState(elapsed=80.0, done=True, passed=True, verdict="a full circuit"))
    assert judge(lab, program(), MobileConfig()) == TrialOutcome(True, "a full circuit")


def test_a_program_that_ends_before_driving_is_said_so_with_its_last_lines():
    outcome = judge(Lab(WallState()), program(1, ["Traceback", "NameError: x"]), MobileConfig())
    assert outcome == TrialOutcome(
        False,
        "program: before its first /cmd_vel the program ended (exit status 1); its last lines: Traceback | NameError: x",
    )


def test_a_program_that_ends_while_driving_is_said_so_with_the_trials_time():
    outcome = judge(Lab(WallState(elapsed=12.34)), program(0), MobileConfig())
    assert outcome == TrialOutcome(False, "program: at 12.3 s of the trial the program ended (exit status 0)")


def test_a_program_that_never_drives_is_said_so(monkeypatch):
    monkeypatch.setattr(wall_trial, "FIRST_COMMAND_S", 0.0)
    outcome = judge(Lab(WallState()), program(), MobileConfig())
    assert outcome == TrialOutcome(False, "program: no /cmd_vel within 0 s of the program's start")


def test_a_simulation_that_falls_behind_is_ended(monkeypatch):
    config = MobileConfig()
    monkeypatch.setattr(wall_trial, "BEHIND_S", -config.rules.time_limit)  # behind at once
    outcome = judge(Lab(WallState(elapsed=3.0)), program(), config)
    assert not outcome.passed
    assert outcome.verdict.startswith("the simulation fell behind: 3.0 s simulated in ")


@pytest.mark.parametrize("lines", [[], ["only"]])
def test_what_an_ended_program_says(lines):
    said = program(2, lines).ended()
    assert said == "the program ended (exit status 2)" + ("; its last lines: only" if lines else "")


def test_an_ended_programs_last_lines_are_read_before_they_are_quoted():
    """A loaded machine gives the output's reader its turn after the program has ended: the lines it
    printed last (why it ended) are read first, then quoted."""
    ended = program(0, ["first"])

    def late():
        time.sleep(0.3)  # the reader's turn comes late
        ended.lines.append("last")

    ended._reader = threading.Thread(target=late)
    ended._reader.start()
    assert ended.ended() == "the program ended (exit status 0); its last lines: first | last"


class GrowingLab(Lab):
    """A lab that holds more memory at each look, as one serving a program's hundred large services does."""

    def __init__(self) -> None:
        super().__init__(WallState(elapsed=1.0))
        self.held: list[bytearray] = []

    def snapshot(self):
        if len(self.held) < 32:  # at most 256 MiB
            self.held.append(bytearray(b"1") * (8 << 20))  # written: really resident
        return super().snapshot()


def test_a_program_that_makes_the_lab_grow_past_its_cap_ends_the_trial(monkeypatch):
    """What the program makes the lab hold counts against it: the trial ends saying how much it grew."""
    monkeypatch.setattr(wall_trial, "LAB_GROWTH_BYTES", 64 << 20)
    config = MobileConfig()
    monkeypatch.setattr(wall_trial, "BEHIND_S", 10.0 - config.rules.time_limit)  # else: ended 10 s after its start
    lab = GrowingLab()
    outcome = judge(lab, program(), config)
    assert not outcome.passed
    assert outcome.verdict.startswith("program: the lab's memory grew by "), outcome
    assert "(its cap: 64 MiB; what it advertised or sent the lab counts against it)" in outcome.verdict
    assert len(lab.held) * 8 >= 64  # it ended once the growth passed the cap, not before
