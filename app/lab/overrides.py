"""Parameter overrides for headless experiments: `hri-lab experiment --set NAME=VALUE`,
`--params FILE.yaml` (the format `param dump` writes), `--sweep NAME=V1,V2,...` and the `set` field
of the /run_experiment and /compare_controllers goals.

The lab's own declarations (app/lab/params.py) validate every value with the parameter server's
rules and messages; each declaration's `offline` puts the value into a plain Setup that
sim.procedures.experiment runs. Parameters without `offline` (f_n_min, which the start sets; the
controller, which --controller picks; the participant; teleop; the rate) do not apply to a trial.
"""

from __future__ import annotations

import itertools

import yaml

from sim.procedures.experiment import SweepPoint
from sim.procedures.trial import Setup

from app.lab.params import LAB_PARAMETERS
from app.ros.params import Parameter, ParameterRefused, ParameterServer, parse_parameter_file
from interfaces.json_value import JSON

VALIDATOR = ParameterServer(LAB_PARAMETERS, lab=None)  # validate() only: nothing is applied
MAX_SWEEP_POINTS = 30

Override = tuple[Parameter, JSON]  # (declaration, validated value)


def declaration(name: str) -> Parameter:
    """A parameter by `name`, `node/name` or `/node/name` (names are unique across the lab's nodes)."""
    node, _, short = name.strip().lstrip("/").rpartition("/")
    found = [p for p in VALIDATOR.declarations.values() if p.name == short and node in ("", p.node)]
    if not found:
        raise ParameterRefused(f"parameter '{short}' cannot be set because it was not declared", 404)
    return found[0]


def validate(name: str, value: JSON) -> Override:
    """The parameter server's checks (type, range, choices, read-only), and that it applies to a trial."""
    param = declaration(name)
    param, value = VALIDATOR.validate(param.node, param.name, value)
    if param.offline is None:
        raise ParameterRefused(
            f"parameter '{param.name}' does not apply to a headless experiment "
            "(the trial starts lifting with f_n_min = 10 N; --controller and --participant choose the rest)"
        )
    return param, value


def _scalar(text: str) -> JSON:
    """A value as `ros2 param set` reads it (YAML: 0.5 is a double, 1 an integer, fast a string)."""
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError:
        return text


def _split(assignment: str) -> tuple[str, str]:
    name, sep, text = assignment.partition("=")
    if not sep or not name.strip():
        raise ParameterRefused(f"'{assignment}' is not NAME=VALUE")
    return name.strip(), text.strip()


def parse_set(assignments: list[str] | str) -> list[Override]:
    """`["alpha=0.5", "k_t=0.2"]` or `"alpha=0.5 k_t=0.2"` -> validated overrides (the last of a name wins)."""
    if isinstance(assignments, str):
        assignments = assignments.split()
    return [validate(name, _scalar(text)) for name, text in map(_split, assignments)]


def parse_file(text: str) -> tuple[list[Override], list[str]]:
    """A `param dump` file -> (validated overrides, names of the parameters ignored because they
    do not apply to a trial). Read-only ones are accepted as at `serve --params`."""
    tree = parse_parameter_file(text)  # the server's limits: size, depth, no aliases
    if not isinstance(tree, dict):
        raise ParameterRefused(
            "a parameter file maps node names to {ros__parameters: {...}}, as `hri-lab param dump` writes it"
        )
    overrides, ignored = [], []
    for node, body in tree.items():
        params = body.get("ros__parameters") if isinstance(body, dict) else None
        if not isinstance(params, dict):
            raise ParameterRefused(f"node '{node}' has no ros__parameters mapping")
        for name, value in params.items():
            param, value = VALIDATOR.validate(str(node), str(name), value, force=True)
            if param.offline is None:
                ignored.append(f"/{param.node}/{param.name}")
            else:
                overrides.append((param, value))
    return overrides, ignored


def setup_of(overrides: list[Override], base: Setup | None = None) -> Setup:
    """The Setup with every override applied, in order."""
    setup = base or Setup()
    for param, value in overrides:
        assert param.offline is not None  # an override is made only of a parameter that has one
        setup = param.offline(setup, value)
    return setup


def changed(overrides: list[Override]) -> dict[str, JSON]:
    """{name: value} of every override that differs from its default (the last of a name counts)."""
    last = {param.name: (param, value) for param, value in overrides}
    return {p.name: v for p, v in last.values() if v != p.default}


def describe(overrides: list[Override]) -> str:
    """The title of a table: every value that differs from its default."""
    defaults = {p.name: p.default for p in VALIDATOR.declarations.values()}
    items = [f"{name} = {value:g} (default {defaults[name]:g})" for name, value in changed(overrides).items()]
    return "parameters: " + (", ".join(items) if items else "the defaults")


def parse_sweep(specs: list[str]) -> list[tuple[Parameter, list[JSON]]]:
    """`["alpha=0.3,0.5,0.8"]` (one parameter) or two of them (a grid) -> validated values."""
    if not 1 <= len(specs) <= 2:
        raise ParameterRefused("a sweep varies one parameter, or two (a grid)")
    axes = []
    for spec in specs:
        name, text = _split(spec)
        values = [validate(name, _scalar(item.strip()))[1] for item in text.split(",") if item.strip()]
        if not values:
            raise ParameterRefused(f"'{spec}' gives no value: NAME=V1,V2,...")
        axes.append((declaration(name), values))
    if len({p.name for p, _ in axes}) < len(axes):
        raise ParameterRefused("a grid needs two different parameters")
    points = 1
    for _, values in axes:
        points *= len(values)
    if points > MAX_SWEEP_POINTS:
        raise ParameterRefused(f"a sweep of {points} points is too big (at most {MAX_SWEEP_POINTS})")
    return axes


def sweep_points(
    axes: list[tuple[Parameter, list[JSON]]], base: list[Override], setup: Setup | None = None
) -> list[SweepPoint]:
    """Every combination of the axes' values, on top of the `base` overrides (on `setup`)."""
    return [
        (
            {p.name: v for (p, _), v in zip(axes, combo)},
            setup_of(base + [(p, v) for (p, _), v in zip(axes, combo)], setup),
        )
        for combo in itertools.product(*(values for _, values in axes))
    ]
