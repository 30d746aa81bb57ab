"""The lab's parameters: one declaration each, with its range; the default comes from the sim's
dataclasses (LiftingParams, WorldConfig's parts, the default participant). `apply`/`read` are
functions of app/lab/commands.py run in the simulation process; `offline` puts a value into a
headless experiment's Setup (sim.procedures.experiment), None where it does not apply."""

from functools import partial

from sim.controllers.builtin import BUILTIN
from sim.controllers.interface import LIFTING_RANGES, LiftingParams
from sim.person.participants import PARTICIPANTS
from sim.world import WorldConfig

from app.lab import commands as cmd
from app.ros.params import Parameter

LIFTING, CONFIG = LiftingParams(), WorldConfig()
PERSON = PARTICIPANTS[CONFIG.participant]  # the live server's participant at start


def _lifting(field: str, description: str, offline: bool = True) -> Parameter:
    """A double of cooperative_lifting that lives in the running controller's LiftingParams (its
    range: LIFTING_RANGES, which a plug-in's start/stop is held to as well)."""
    return Parameter(
        "cooperative_lifting",
        field,
        "double",
        getattr(LIFTING, field),
        description,
        LIFTING_RANGES[field],
        apply=partial(cmd.set_lifting, field=field),
        read=partial(cmd.get_lifting, field=field),
        offline=(lambda setup, value: setup.with_lifting(field, value)) if offline else None,
    )


def _person(name: str, field: str, description: str, low: float, high: float) -> Parameter:
    """A double of the scripted participant (sim.person.human.Participant field); in an
    experiment it is set for every participant."""
    return Parameter(
        "human",
        name,
        "double",
        getattr(PERSON, field),
        description,
        (low, high),
        apply=partial(cmd.set_person, field=field),
        read=partial(cmd.get_person, field=field),
        offline=lambda setup, value: setup.with_person(field, value),
    )


def _config(name: str, part: str, field: str, description: str, low: float, high: float) -> Parameter:
    """A double of node `sim`: a field of a part of the world's configuration (sensor, box, plate_contact)."""
    return Parameter(
        "sim",
        name,
        "double",
        getattr(getattr(CONFIG, part), field),
        description,
        (low, high),
        apply=partial(cmd.set_config, part=part, field=field),
        read=partial(cmd.get_config, part=part, field=field),
        offline=lambda setup, value: setup.with_config(part, field, value),
    )


F_N_MIN_RANGE = LIFTING_RANGES["f_n_min"]  # N; also the range of the start service's force

LAB_PARAMETERS = [
    _lifting(
        "f_n_min",
        "lower end of the normal-force band (N); set by start/stop_cooperative_lifting (a trial starts with 10 N)",
        offline=False,
    ),
    _lifting("f_n_band", "width of the band (N): f_n_max = f_n_min + f_n_band"),
    _lifting("mu", "friction coefficient the controller assumes"),
    _lifting("alpha", "safety margin on the friction cone (< 1)"),
    _lifting("k_n", "normal gain ((m/s)/N)"),
    _lifting("k_t", "tangential gain ((m/s)/N)"),
    _lifting("k_w", "rotational gain ((rad/s)/Nm)"),
    _lifting("moment_deadband", "moments below this are noise (Nm)"),
    _lifting("v_max", "linear speed limit of the command (m/s)"),
    _lifting("w_max", "angular speed limit of the command (rad/s)"),
    _lifting("filter_hz", "cut-off of the controller's low-pass on F_ext (Hz, 0 = none)"),
    Parameter(
        "cooperative_lifting",
        "controller",
        "string",
        "sp",
        "the lifting controller: sp (Single Point) or patch (patch-aware); reads 'plugin' while "
        "a file given to `serve --controller` runs, 'node' while a node's commands drive the robot",
        choices=BUILTIN,
        apply=cmd.set_controller,
        read=cmd.controller_choice,
    ),
    Parameter("keytwist", "linear_speed", "double", 0.1, "teleop linear speed (m/s)", (0.0, 0.5)),
    Parameter("keytwist", "angular_speed", "double", 0.1, "teleop angular speed (rad/s)", (0.0, 1.0)),
    Parameter(
        "sim",
        "rate_hz",
        "integer",
        round(1.0 / CONFIG.dt),
        "control rate of the simulation (Hz)",
        (1000, 1000),
        read_only=True,
    ),
    _config("sensor_noise_std", "sensor", "force_noise_std", "F_ext force noise, standard deviation (N)", 0.0, 10.0),
    _config(
        "sensor_moment_noise_std", "sensor", "moment_noise_std", "F_ext moment noise, standard deviation (Nm)", 0.0, 1.0
    ),
    _config("filter_cutoff_hz", "sensor", "filter_cutoff_hz", "F_ext low-pass cut-off (Hz, 0 = none)", 0.0, 500.0),
    _config("box_mass", "box", "mass", "mass of the box (kg)", 0.05, 5.0),
    _config(
        "contact_stiffness",
        "plate_contact",
        "normal_stiffness",
        "normal stiffness of the plate contact (N/m)",
        1.0e3,
        1.0e5,
    ),
    Parameter(
        "sim",
        "command_period",
        "double",
        CONFIG.command_period,
        "a node's command on /cartesian_velocity_controller/command older than this stops the robot "
        "(s of simulation time; franka's communication constraints)",
        (0.01, 10.0),
        apply=cmd.set_command_period,
        read=cmd.get_command_period,
    ),
    _person("squeeze_force", "squeeze_force", "force the person presses the box with (N)", 0.0, 60.0),
    _person("speed", "peak_speed", "peak hand speed of the pick-and-place path (m/s)", 0.01, 0.5),
    Parameter(
        "human",
        "profile",
        "string",
        CONFIG.participant,
        "the scripted participant",
        choices=tuple(PARTICIPANTS),
        apply=cmd.set_profile,
        read=partial(cmd.get_person, field="name"),
    ),
]
