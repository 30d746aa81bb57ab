"""What the server asks of the simulation: functions fn(world, *args), run in the simulation
process between two steps (Lab.call). They live at module level so they travel by name."""
from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from sim.controllers.interface import stop_lifting
from sim.person.human import PARTICIPANTS
from sim.controllers.patch import PatchController
from sim.controllers.plugin import builtin
from sim.controllers.sp import SPController
from sim.world import World


# --- lifting and motion ---------------------------------------------------------------------
def start_lifting(world: World, force: float, controller: str = "") -> str:
    """The start service: optionally select a built-in controller first, then start."""
    if controller:
        set_controller(world, controller)
    return world.start_lifting(force)


def reset_world(world: World) -> None:
    """The reset service: lifting stopped (else the scripted person would start over at once),
    then the world reset."""
    try:
        world.stop_lifting()  # a plug-in's own stop handler, as the stop service runs it
    except Exception:  # noqa: BLE001 - a failing plug-in handler: the lab's stop
        stop_lifting(world.params)
    world.reset()


def lifting_state(world: World) -> tuple[bool, float, float, float]:
    """(running, f_n_min, f_n_band, f_n_max) read in one go."""
    p = world.params
    return p.running, p.f_n_min, p.f_n_band, p.f_n_max


def recover(world: World) -> str | None:
    """Clear the robot's error; returns the error that was cleared (None if there was none)."""
    error = world.error
    world.recover()
    return error


def begin_move_to_start(world: World) -> float:
    """Start the joint motion to the start pose; its duration (s)."""
    if world.params.running:
        raise RuntimeError("cooperative lifting is running: stop it first")
    if world.error:
        raise RuntimeError(f"the robot is in error ({world.error}): call /error_recovery first")
    return world.move_to_start().duration


def motion_progress(world: World) -> tuple[float, bool, str | None]:
    """(progress 0..1, still moving, robot error) of the motion to the start pose."""
    motion = world.motion
    return (motion.progress if motion else 1.0), motion is not None, world.error


def set_hand_target(world: World, position: np.ndarray) -> None:
    world.human.set_target(position)


def controller_name(world: World) -> str:
    return type(world.controller).__name__


def controller_choice(world: World) -> str:
    """The `controller` parameter: "sp", "patch", or "plugin" (a file given to `serve --controller`)."""
    return {SPController: "sp", PatchController: "patch"}.get(type(world.controller), "plugin")


# --- parameters: apply(world, value) and read(world) ----------------------------------------
def set_lifting(world: World, value: Any, field: str) -> None:
    setattr(world.params, field, value)


def get_lifting(world: World, field: str) -> Any:
    return getattr(world.params, field)


def set_controller(world: World, value: str) -> None:
    world.set_controller(builtin(value))


def set_person(world: World, value: Any, field: str) -> None:
    world.set_participant(replace(world.human.participant, **{field: value}))


def get_person(world: World, field: str) -> Any:
    return getattr(world.human.participant, field)


def set_profile(world: World, value: str) -> None:
    world.set_participant(PARTICIPANTS[value])


def set_config(world: World, value: Any, part: str, field: str) -> None:
    """A field of the world's configuration: part "sensor", "box" or "plate_contact"."""
    getattr(world, f"set_{part}")(**{field: value})


def get_config(world: World, part: str, field: str) -> Any:
    return getattr(getattr(world.config, part), field)
