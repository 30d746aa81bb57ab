"""mkdocs hook: the reference pages' tables, generated at build time from the code's own declarations.

A page says `<!-- generated: NAME -->` where a table goes; NAME is a key of GENERATORS. Each table
is read from the one place the fact is declared: the HTTP API from `create_app().openapi()`, the CLI
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

    return {"LiftingParams": LiftingParams(), "TrialRules": TrialRules()}


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
    from app.api.app import create_app

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
        sub.formatter_class = functools.partial(argparse.HelpFormatter, width=100)  # not the terminal's
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
    """rosapi's services as the lab answers them, and which of them change something."""
    from app.rosbridge import rosapi as api

    rows = [
        [f"`{name}`", "changes (needs the token)" if name in api.WRITING else "reads"] for name in sorted(api.NAMES)
    ]
    return _table(["service", "access"], rows)


def rosbridge_ops() -> str:
    """The ops a rosbridge connection dispatches (app/rosbridge/ops.py), and which need the token."""
    from app.rosbridge.ops import OPS

    def token(name: str) -> str:
        if name == "call_service":  # decided per service (capabilities/call_service.py)
            return "yes, but for rosapi's reading services (below)"
        return "yes" if OPS[name].mutating else ""

    return _table(
        ["op", "needs the token (when the lab has one)"], [[f"`{name}`", token(name)] for name in sorted(OPS)]
    )


GENERATORS: dict[str, Callable[[], str]] = {
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
