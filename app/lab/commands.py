"""Every command the server sends into the simulation: functions fn(world, *args), run in the
simulation process between two steps (`lab.call(fn, *args)`, app/runtime/process.py). This is the
only way into the world from app/: services, parameters, actions, teleop and the 3D view all call
these. They live at module level so they travel by name. Those that only read the world are marked
`@reads_world` (app/runtime/loop.py): reading one leaves an idle lab idle."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from sim.controllers.builtin import builtin, builtin_name
from sim.controllers.external import ExternalCommand
from sim.controllers.interface import start_lifting as start_band
from sim.controllers.interface import stop_lifting as stop_band
from sim.person.participants import PARTICIPANTS
from sim.world import World, WorldConfig

from app.runtime.loop import reads_world
from interfaces.json_value import JSON


# --- lifting and motion ---------------------------------------------------------------------
def start_lifting(world: World, force: float, controller: str = "") -> str:
    """The start service: optionally select a built-in controller first, then start."""
    if controller:
        set_controller(world, controller)
    return world.start_lifting(force)


def stop_lifting(world: World) -> str:
    """The stop service (the controller's handler)."""
    return world.stop_lifting()


def reset_world(world: World) -> None:
    """The reset service: lifting stopped (else the scripted person would start over at once),
    then the world reset."""
    try:
        world.stop_lifting()  # a plug-in's own stop handler, as the stop service runs it
    except Exception:  # noqa: BLE001 - a failing plug-in handler: the lab's stop
        stop_band(world.params)
    world.reset()


@reads_world
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


@reads_world
def motion_progress(world: World) -> tuple[float, bool, str | None]:
    """(progress 0..1, still moving, robot error) of the motion to the start pose."""
    motion = world.motion
    return (motion.progress if motion else 1.0), motion is not None, world.error


def stop_motion(world: World) -> None:
    """Cancel move_to_start: the joints brake to rest."""
    world.stop_motion()


def start_jog(world: World, twist_base: np.ndarray) -> None:
    """Teleop: move the EE with twist_base (m/s, rad/s) for a moment (only while lifting is stopped)."""
    world.start_jog(twist_base)


def set_hand_target(world: World, position: np.ndarray) -> None:
    """The palm's target (m, base frame): the person follows it (the 3D view's gizmo)."""
    world.human.set_target(position)


@reads_world
def world_config(world: World) -> WorldConfig:
    """The world's configuration as it is now (parameters change it)."""
    return world.config


@reads_world
def scene_geometry(world: World) -> dict[str, tuple[float, ...]]:
    """What the 3D view draws that does not move: plate (width, height, offset), box size, palm size (m)."""
    cfg = world.config
    return {
        "plate": (cfg.plate.width, cfg.plate.height, cfg.plate.offset),
        "box": tuple(cfg.box.size),
        "palm": tuple(cfg.palm_size),
    }


@reads_world
def controller_name(world: World) -> str:
    return type(world.controller).__name__


@reads_world
def controller_choice(world: World) -> str:
    """The `controller` parameter: "sp", "patch", "node" (a node's commands drive the robot) or
    "plugin" (a file given to `serve --controller`)."""
    if isinstance(world.controller, ExternalCommand):
        return "node"
    return builtin_name(world.controller) or "plugin"


def external_twist(world: World, twist_base: np.ndarray) -> None:
    """A node's command on /cartesian_velocity_controller/command (the one path of node commands
    into the simulation): the first one selects the external-command controller."""
    if not isinstance(world.controller, ExternalCommand):
        world.set_controller(ExternalCommand(get_command_period(world)))
    assert isinstance(world.controller, ExternalCommand)
    world.controller.command(twist_base)


def set_command_period(world: World, value: float) -> None:
    """The external command's watchdog period (s; parameter /sim command_period), now and after resets."""
    world.config = replace(world.config, command_period=value)
    if isinstance(world.controller, ExternalCommand):
        world.controller.period = value


@reads_world
def get_command_period(world: World) -> float:
    return world.config.command_period


def lifting_effect(world: World, start: bool, force: float = 0.0) -> None:
    """What a node's start/stop service means for the lab: the band the person expects
    (f_n_min = force, f_n_max = force + f_n_band) and the running flag; no controller change."""
    if start:
        start_band(world.params, force)
    else:
        stop_band(world.params)


# --- parameters: apply(world, value) and read(world) ----------------------------------------
def set_lifting(world: World, value: JSON, field: str) -> None:
    setattr(world.params, field, value)


@reads_world
def get_lifting(world: World, field: str) -> JSON:
    return getattr(world.params, field)


def set_controller(world: World, value: str) -> None:
    world.set_controller(builtin(value))


def set_person(world: World, value: Any, field: str) -> None:  # Any: a field of its own type (validated)
    world.set_participant(replace(world.human.participant, **{field: value}))


@reads_world
def get_person(world: World, field: str) -> JSON:
    return getattr(world.human.participant, field)


def set_profile(world: World, value: str) -> None:
    world.set_participant(PARTICIPANTS[value])


_CONFIGURE = {"sensor": World.set_sensor, "box": World.set_box, "plate_contact": World.set_plate_contact}


def set_config(world: World, value: JSON, part: str, field: str) -> None:
    """A field of the world's configuration: part "sensor", "box" or "plate_contact"."""
    _CONFIGURE[part](world, **{field: value})


@reads_world
def get_config(world: World, part: str, field: str) -> JSON:
    return getattr(getattr(world.config, part), field)
