"""The lab's parameters (DESIGN.md section 7): one declaration each."""
from dataclasses import replace

from sim.human import PARTICIPANTS
from sim.plugin import BUILTIN, builtin

from .params import Parameter


def _lifting(field: str, description: str, default: float, low: float, high: float) -> Parameter:
    """A double of cooperative_lifting that lives in the running controller's LiftingParams."""
    return Parameter(
        "cooperative_lifting", field, "double", default, description, (low, high),
        apply=lambda world, value: setattr(world.params, field, value),
        read=lambda world: getattr(world.params, field),
    )


def _person(name: str, field: str, description: str, default: float, low: float, high: float) -> Parameter:
    """A double of the scripted participant (sim.human.Participant field)."""
    return Parameter(
        "human", name, "double", default, description, (low, high),
        apply=lambda world, value: world.set_participant(replace(world.human.participant, **{field: value})),
        read=lambda world: getattr(world.human.participant, field),
    )


F_N_MIN_RANGE = (0.0, 60.0)  # N; also the range of the start service's force

LAB_PARAMETERS = [
    _lifting("f_n_min", "lower end of the normal-force band (N); set by start/stop_cooperative_lifting", 0.0, *F_N_MIN_RANGE),
    _lifting("f_n_band", "width of the band (N): f_n_max = f_n_min + f_n_band", 5.0, 0.5, 30.0),
    _lifting("mu", "friction coefficient the controller assumes", 0.5, 0.05, 2.0),
    _lifting("alpha", "safety margin on the friction cone (< 1)", 0.8, 0.1, 1.0),
    _lifting("k_n", "normal gain ((m/s)/N)", 0.005, 0.0, 0.1),
    _lifting("k_t", "tangential gain ((m/s)/N)", 0.1, 0.0, 1.0),
    _lifting("k_w", "rotational gain ((rad/s)/Nm)", 1.0, 0.0, 10.0),
    _lifting("moment_deadband", "moments below this are noise (Nm)", 0.1, 0.0, 2.0),
    _lifting("v_max", "linear speed limit of the command (m/s)", 0.5, 0.0, 1.7),
    _lifting("w_max", "angular speed limit of the command (rad/s)", 1.0, 0.0, 2.5),
    _lifting("filter_hz", "cut-off of the controller's low-pass on F_ext (Hz, 0 = none)", 10.0, 0.0, 500.0),
    Parameter("cooperative_lifting", "controller", "string", "sp",
              "the lifting controller: sp (Single Point) or patch (patch-aware); a plug-in is chosen at start",
              choices=BUILTIN, apply=lambda world, v: world.set_controller(builtin(v))),
    Parameter("keytwist", "linear_speed", "double", 0.1, "teleop linear speed (m/s)", (0.0, 0.5)),
    Parameter("keytwist", "angular_speed", "double", 0.1, "teleop angular speed (rad/s)", (0.0, 1.0)),
    Parameter("sim", "rate_hz", "integer", 1000, "control rate of the simulation (Hz)", (1000, 1000), read_only=True),
    Parameter("sim", "sensor_noise_std", "double", 0.5, "F_ext force noise, standard deviation (N)", (0.0, 10.0),
              apply=lambda world, v: world.set_sensor(force_noise_std=v),
              read=lambda world: world.config.sensor.force_noise_std),
    Parameter("sim", "sensor_moment_noise_std", "double", 0.05, "F_ext moment noise, standard deviation (Nm)", (0.0, 1.0),
              apply=lambda world, v: world.set_sensor(moment_noise_std=v),
              read=lambda world: world.config.sensor.moment_noise_std),
    Parameter("sim", "filter_cutoff_hz", "double", 0.0, "F_ext low-pass cut-off (Hz, 0 = none)", (0.0, 500.0),
              apply=lambda world, v: world.set_sensor(filter_cutoff_hz=v),
              read=lambda world: world.config.sensor.filter_cutoff_hz),
    Parameter("sim", "box_mass", "double", 1.0, "mass of the box (kg)", (0.05, 5.0),
              apply=lambda world, v: world.set_box(mass=v), read=lambda world: world.config.box.mass),
    Parameter("sim", "contact_stiffness", "double", 2.0e4, "normal stiffness of the plate contact (N/m)", (1.0e3, 1.0e5),
              apply=lambda world, v: world.set_plate_contact(normal_stiffness=v),
              read=lambda world: world.config.plate_contact.normal_stiffness),
    _person("squeeze_force", "squeeze_force", "force the person presses the box with (N)", 14.0, 0.0, 60.0),
    _person("speed", "peak_speed", "peak hand speed of the pick-and-place path (m/s)", 0.08, 0.01, 0.5),
    Parameter("human", "profile", "string", "calm", "the scripted participant", choices=tuple(PARTICIPANTS),
              apply=lambda world, v: world.set_participant(PARTICIPANTS[v]),
              read=lambda world: world.human.participant.name),
]
