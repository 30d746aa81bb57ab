"""mkdocs hook: the reference pages' tables, generated at build time from the code's own declarations.

A page says `<!-- generated: NAME -->` where a table goes; NAME is a key of GENERATORS. Each table
is read from the one place the fact is declared: the HTTP API from `create_app().openapi()` (app/serving/compose.py), the CLI
from `app.cli.main.build_parser()`, the parameters from `app.lab.params.LAB_PARAMETERS`, the topics
from `app.lab.topics.TOPICS`, the services and actions from `app.lab.services.SERVICES` and
`app.lab.actions.ACTIONS`, rosbridge's ops from its connection's handlers, rosapi's services from
`app.rosbridge.rosapi`. Nothing here is written
by hand a second time, so the pages cannot drift from the code.

A page's numbers that are the code's defaults are placeholders too, `{{ Class.field }}` or
`{{ Class.field | unit }}` (the field in SI units shown in another, e.g. `{{ TrialRules.max_slip | cm }}`),
filled from the classes in `DEFAULTS` (tests/test_one_source.py fails on a hand copy).
"""

from __future__ import annotations

import argparse
import functools
import math
import re
from collections.abc import Callable
from typing import Any

MARKER = re.compile(r"<!-- generated: ([a-z-]+) -->")
VALUE = re.compile(r"\{\{ *([A-Za-z]+)\.([a-z_]+) *(?:\| *([a-z]+) *)?\}\}")
SCALE = {"cm": 100.0, "mm": 1000.0, "ms": 1000.0}  # from the field's SI unit (m, s)


@functools.cache
def _defaults() -> dict[str, Any]:
    """The classes whose defaults the pages quote, by the name a placeholder gives."""
    from sim.controllers.interface import LiftingParams
    from sim.monitor import TrialRules

    from app.runtime.loop import SimulationLoop

    return {"LiftingParams": LiftingParams(), "TrialRules": TrialRules(), "SimulationLoop": SimulationLoop}


def value(match: re.Match[str]) -> str:
    """A placeholder's number: the field's default, in the unit it names (`:g`, so 0.5 not 0.50)."""
    name, field, unit = match.groups()
    defaults = _defaults()
    if name not in defaults or not hasattr(defaults[name], field) or (unit and unit not in SCALE):
        raise ValueError(f"unknown placeholder {match.group(0)}: a field of {sorted(defaults)}, units {sorted(SCALE)}")
    number = float(getattr(defaults[name], field)) * (SCALE[unit] if unit else 1.0)
    return f"{round(number, 9):g}"


def _cell(text: Any) -> str:
    """Text for a Markdown table cell."""
    return str(text).replace("|", "\\|").replace("\n", " ").strip()


def _table(header: list[str], rows: list[list[Any]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(_cell(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


@functools.cache
def _openapi() -> dict:
    from app.serving.compose import create_app

    return create_app().openapi()  # the app is built, never served: no simulation runs


def http_api() -> str:
    """Every route: method, path, summary and the status codes it documents, by tag."""
    by_tag: dict[str, list[list[Any]]] = {}
    for path, operations in _openapi()["paths"].items():
        for method, op in operations.items():
            if method not in ("get", "put", "post", "delete", "patch"):
                continue
            summary = op.get("summary") or ""
            description = (op.get("description") or "").split("\n\n")[0]
            text = summary if not description or description == summary else f"{summary}: {description}"
            codes = ", ".join(sorted(op.get("responses", {})))
            by_tag.setdefault((op.get("tags") or ["other"])[0], []).append(
                [f"`{method.upper()}`", f"`{path}`", text, codes]
            )
    out = []
    for tag, rows in by_tag.items():
        out += [f"### {tag}", "", _table(["method", "path", "what", "status codes"], rows), ""]
    return "\n".join(out)


def _subcommands(parser: argparse.ArgumentParser) -> list[tuple[str, argparse.ArgumentParser]]:
    """(full command, parser) of every command and subcommand, depth first."""
    out = []
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                out.append((name, sub))
                out += [(f"{name} {child}", p) for child, p in _subcommands(sub)]
    return out


def cli() -> str:
    """Each `hri-lab` command: what it does, its usage and its options, as argparse prints them."""
    from app.cli.main import build_parser

    parser = build_parser()
    helps: dict[str, str] = {}
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            helps = {a.dest: a.help or "" for a in action._choices_actions}
    out = []
    for name, sub in _subcommands(parser):
        if any(isinstance(a, argparse._SubParsersAction) for a in sub._actions):
            out += [f"### hri-lab {name}", "", helps.get(name, sub.description or ""), ""]
            for action in sub._actions:
                if isinstance(action, argparse._SubParsersAction):
                    said = {a.dest: a.help or "" for a in action._choices_actions}
                    if any(said.values()):  # subcommands declared with help: a table of them
                        rows = [[f"`hri-lab {name} {child}`", said.get(child, "")] for child in action.choices]
                        out += [_table(["command", "what"], rows), ""]
            continue
        sub.prog = f"hri-lab {name}"
        kind = sub.formatter_class if isinstance(sub.formatter_class, type) else argparse.HelpFormatter
        sub.formatter_class = functools.partial(kind, width=100)  # not the terminal's; the examples kept as written
        out += [
            f"### hri-lab {name}",
            "",
            helps.get(name.split()[0], "") if " " not in name else "",
            "",
            "```",
            sub.format_help().rstrip(),
            "```",
            "",
        ]
    return "\n".join(out)


def parameters() -> str:
    """Every parameter of every node: type, default, range or choices, read-only, description."""
    from app.lab.params import LAB_PARAMETERS

    rows = []
    for p in LAB_PARAMETERS:
        allowed = f"{p.range[0]:g} .. {p.range[1]:g}" if p.range else ", ".join(p.choices)
        rows.append(
            [
                f"`{p.node}`",
                f"`{p.name}`",
                p.type,
                f"`{p.default}`",
                allowed,
                "yes" if p.read_only else "",
                p.description,
            ]
        )
    return _table(["node", "name", "type", "default", "range / choices", "read-only", "description"], rows)


def topics() -> str:
    """Every topic the lab publishes, with its message type."""
    from app.lab.topics import TOPICS

    return _table(["topic", "type"], [[f"`{t.name}`", f"`{t.type}`"] for t in TOPICS])


def services() -> str:
    """Every service the lab declares: its type, description and .srv text."""
    from app.lab.services import EXERCISES, SERVICES

    out = []
    for s in SERVICES:
        exercise = " *(an exercise: `serve --exercises` leaves it to a student's node)*" if s.name in EXERCISES else ""
        out += [f"### `{s.name}`", "", f"`{s.type}` — {s.description}{exercise}", "", "```", s.srv, "```", ""]
    return "\n".join(out)


def actions() -> str:
    """Every action the lab declares: its type, description and .action text."""
    from app.lab.actions import ACTIONS

    out = []
    for a in ACTIONS:
        out += [f"### `{a.name}`", "", f"`{a.type}` — {a.description}", "", "```", a.definition, "```", ""]
    return "\n".join(out)


def rosapi() -> str:
    """rosapi's services as the lab answers them (rosbridge's service table), and which change something."""
    from app.rosbridge import rosapi as api
    from app.rosbridge.services import REPUBLISH

    rows = [
        [f"`{s.name}`", f"`{s.type}`", "changes (needs the token)" if s.writes else "reads"]
        for s in sorted(api.SERVICES, key=lambda s: s.name)
    ]
    rows.append(
        [f"`{REPUBLISH.name}`", f"`{REPUBLISH.type}`", "changes (needs the token)" if REPUBLISH.writes else "reads"]
    )
    return _table(["service", "type", "access"], rows)


def rosbridge_ops() -> str:
    """The ops a rosbridge connection dispatches (app/rosbridge/ops.py), and which need the token."""
    from app.rosbridge.ops import OPS

    def token(name: str) -> str:
        if name == "call_service":  # decided per service: its entry's flag (app/rosbridge/services.py)
            return "yes, but for rosapi's reading services and /republish_tfs (below)"
        return "yes" if OPS[name].mutating else ""

    return _table(
        ["op", "needs the token (when the lab has one)"], [[f"`{name}`", token(name)] for name in sorted(OPS)]
    )


def mobile_topics() -> str:
    """The mobile world's topics (`serve --world mobile`), with their types."""
    from app.mobile.topics import TOPICS

    return _table(["topic", "type"], [[f"`{t.name}`", f"`{t.type}`"] for t in TOPICS])


def mobile_figures() -> str:
    """The base's and the scanner's figures, as the simulation uses them."""
    from sim.mobile.base import BaseSpec
    from sim.mobile.lidar import LidarSpec
    from sim.mobile.world import WHEEL_RADIUS_ERROR_SIGMA, MobileConfig

    b, lidar = BaseSpec(), LidarSpec()
    rows = [
        ["wheel separation", f"{b.wheel_separation} m"],
        ["wheel radius", f"{b.wheel_radius} m"],
        ["top speed", f"{b.max_linear} m/s, {b.max_angular} rad/s"],
        ["accelerations (the lab's choice)", f"{b.max_linear_acceleration} m/s², {b.max_angular_acceleration} rad/s²"],
        ["footprint (contact) radius", f"{b.footprint_radius} m"],
        ["command watchdog", f"{b.command_timeout} s without a /cmd_vel: the base stops"],
        ["wheel radius error (a seeded world's odometry drift)", f"σ = {WHEEL_RADIUS_ERROR_SIGMA:.1%} per wheel"],  # noqa: RUF001 - the standard deviation, as the datasheets write it
        ["control period", f"{MobileConfig().dt * 1e3:g} ms ({1 / MobileConfig().dt:g} Hz)"],
        ["scan", f"{lidar.rays} rays, {360 / lidar.rays:g}° apart from straight ahead, counter-clockwise"],
        ["scan range", f"{lidar.range_min}-{lidar.range_max} m (else +inf), {lidar.rate_hz:g} Hz"],
        [
            "scan noise (LDS-01 accuracy as 2σ)",  # noqa: RUF001 - the standard deviation, as the datasheets write it
            f"σ = {lidar.near_sigma * 1e3:g} mm below {lidar.near_limit} m, {lidar.far_sigma_ratio:.1%} of the range beyond",  # noqa: RUF001 - the standard deviation, as the datasheets write it
        ],
        ["base_scan in base_footprint", f"({lidar.offset_xy[0]}, {lidar.offset_xy[1]}, {lidar.height}) m"],
    ]
    return _table(["figure", "value"], rows)


def mobile_rules() -> str:
    """The wall-following grade's rule and what its seed draws."""
    from sim.mobile import arena, world
    from sim.mobile.monitor import WallRules

    from app.grading import wall

    r = WallRules()
    rows = [
        ["trials per file (`--trials`)", wall.TRIALS],
        ["pass mark", f"{wall.PASS_MARK:g} % of the trials"],
        ["full circuit", f"360° about the obstacle's centre, either way, within {r.time_limit:g} s"],
        ["band", f"{r.band[0]:.2f}-{r.band[1]:.2f} m from the obstacle's surface (from base_footprint)"],
        ["time outside the band", f"at most {r.outside_band_max:g} s of the trial"],
        ["collision", "any contact with the obstacle or the arena's wall"],
        ["stall", f"less than {r.stall_distance} m of motion in {r.stall_window:g} s"],
        ["arena", f"{2 * arena.DRAWN_HALF_SIZE_XY[0]:g} x {2 * arena.DRAWN_HALF_SIZE_XY[1]:g} m, walled"],
        [
            "obstacle (drawn)",
            f"a cylinder of radius {arena.CYLINDER_RADIUS_RANGE[0]}-{arena.CYLINDER_RADIUS_RANGE[1]} m or a box of "
            f"half sides {arena.BOX_HALF_SIDE_RANGE[0]}-{arena.BOX_HALF_SIDE_RANGE[1]} m at any yaw, its centre within "
            f"{arena.CENTER_OFFSET_MAX} m of the arena's",
        ],
        [
            "start pose (drawn)",
            f"{world.START_DISTANCE_RANGE[0]}-{world.START_DISTANCE_RANGE[1]} m from the obstacle's surface, facing its "
            f"centre within {round(math.degrees(world.START_HEADING_SPREAD))}°",
        ],
    ]
    return _table(["rule", "value"], rows)


GENERATORS: dict[str, Callable[[], str]] = {
    "mobile-topics": mobile_topics,
    "mobile-figures": mobile_figures,
    "mobile-rules": mobile_rules,
    "http-api": http_api,
    "cli": cli,
    "parameters": parameters,
    "topics": topics,
    "services": services,
    "actions": actions,
    "rosapi": rosapi,
    "rosbridge-ops": rosbridge_ops,
}


def on_page_markdown(markdown: str, page: Any, config: Any, files: Any) -> str:
    return VALUE.sub(value, MARKER.sub(lambda m: GENERATORS[m.group(1)](), markdown))
