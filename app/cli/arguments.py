"""The arguments several `hri-lab` commands share, each declared once (its flag, type, default and
help): the lab's URL, the processes and the cluster a batch runs on, the controller, a parameters
file, the grading reports' options, the recordings and figures of trials; and the commands' own
shape: a command's parser with its help and its examples (printed by `--help`, parsed by
tests/app/cli/test_main.py; `declared` reads them from the docstring of the function that adds its
arguments), its code imported when it runs. app/cli/main.py declares the commands
with these; the ros2-like client commands (client.py, bag.py) take their --url from here too.
"""

from __future__ import annotations

import argparse
import importlib
import inspect
import os
import re
import sys
from collections.abc import Callable

from app.grading.report import PUBLIC_SEED

DEFAULT_URL = "http://127.0.0.1:8000"  # the lab as `hri-lab serve` starts it
URL_ENV, GRADE_SEED_ENV, SCHEDULER_ENV = "HRI_LAB_URL", "HRI_LAB_GRADE_SEED", "HRI_LAB_SCHEDULER"
Parser = argparse.ArgumentParser
Subparsers = argparse._SubParsersAction


# --- types ------------------------------------------------------------------------------------------
def positive_int(text: str) -> int:
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError("must be >= 1")
    return value


def fraction(text: str) -> float:
    value = float(text)
    if not 0.0 < value <= 1.0:
        raise argparse.ArgumentTypeError(f"a fraction in (0, 1], got {text}")
    return value


def scheduler_address(text: str) -> str | None:
    """A Dask scheduler's address: [tcp|tls://]HOST:PORT ("" = none)."""
    if not text:
        return None
    if not re.fullmatch(r"((tcp|tls)://)?[A-Za-z0-9._\-\[\]:]+:\d{1,5}", text):
        raise argparse.ArgumentTypeError(f"{text!r} is not a Dask scheduler's address, e.g. tcp://HOST:8786")
    return text


# --- a command --------------------------------------------------------------------------------------
def command(sub: Subparsers, name: str, help: str, examples: tuple[str, ...], **kwargs) -> Parser:
    """A command's parser: its one-line help (the command list's), its examples under `--help`
    (each a whole command line, `hri-lab NAME ...`, with what it does after a `#`)."""
    if wrong := [e for e in examples if not e.startswith(f"hri-lab {name}")]:
        raise ValueError(f"an example of `hri-lab {name}` is a whole command line of it: {wrong}")
    epilog = "examples:\n" + "\n".join(f"  {e}" for e in examples) if examples else None
    return sub.add_parser(
        name, help=help, epilog=epilog, formatter_class=argparse.RawDescriptionHelpFormatter, **kwargs
    )


def declared(name: str) -> Callable[[Callable[[Parser], None]], Callable[[Subparsers], None]]:
    """A command declared by the function that adds its arguments to its parser, as click and typer
    read a command's help: the function's docstring gives the command's one-line help (its first
    paragraph) and its examples (each line after, a whole command line: `command`)."""

    def declare(add_arguments: Callable[[Parser], None]) -> Callable[[Subparsers], None]:
        about, _, rest = inspect.cleandoc(add_arguments.__doc__ or "").partition("\n\n")
        examples = tuple(line.strip() for line in rest.splitlines() if line.strip())

        def add(sub: Subparsers) -> None:
            add_arguments(command(sub, name, " ".join(about.split()), examples))

        return add

    return declare


def runs(module: str) -> Callable[[argparse.Namespace], int]:
    """The command `module.run(args)`, its module imported when the command runs (the client
    commands then start without loading the simulation: numba, pinocchio)."""

    def run(args: argparse.Namespace) -> int:
        try:
            return importlib.import_module(module).run(args)
        except Exception as exc:
            # the runner is imported by the commands that can raise its ClusterUnreachable, not by the others
            runner = sys.modules.get("sim.procedures.runner")
            if runner is None or not isinstance(exc, runner.ClusterUnreachable):
                raise
            print(f"hri-lab {args.command}: {exc}", file=sys.stderr)  # --scheduler names no cluster: one line, exit 1
            return 1

    return run


# --- shared arguments -------------------------------------------------------------------------------
def url(parser: Parser, help: str | None = None, start_one: bool = False) -> None:
    """--url: the lab to talk to (default $HRI_LAB_URL or DEFAULT_URL); start_one: none by default
    (the command starts a lab of its own, as roslaunch starts roscore)."""
    parser.add_argument(
        "--url",
        default=None if start_one else os.environ.get(URL_ENV, DEFAULT_URL),
        help=help or f"the lab (default ${URL_ENV} or {DEFAULT_URL}); changes carry $HRI_LAB_TOKEN",
    )


def url_parent() -> Parser:
    """A parent parser of only --url, for a family of subcommands (`service call`, `topic echo` ...)."""
    parent = argparse.ArgumentParser(add_help=False)
    url(parent)
    return parent


def jobs(parser: Parser, what: str) -> None:
    """--jobs N: `what` in N processes here (default one per core)."""
    parser.add_argument(
        "--jobs",
        type=positive_int,
        default=os.cpu_count() or 1,
        help=f"{what} run in this many processes (default: one per core; the same results)",
    )


def scheduler(parser: Parser, what: str) -> None:
    """--scheduler: a Dask cluster instead of --jobs (docs/course-scale.md)."""
    parser.add_argument(
        "--scheduler",
        metavar="tcp://HOST:8786",
        type=scheduler_address,
        default=os.environ.get(SCHEDULER_ENV),
        help=f"run {what} as a task on this Dask cluster instead of --jobs processes here "
        f"(default ${SCHEDULER_ENV}; the same results)",
    )


def unsandboxed(parser: Parser, what: str) -> None:
    """--unsandboxed: students' code outside bubblewrap, where bwrap cannot run (grade, grade-wall)."""
    parser.add_argument(
        "--unsandboxed",
        action="store_true",
        help=f"run the {what} without bubblewrap (still in processes of their own) where bwrap cannot run",
    )


def quiet(parser: Parser, what: str = "no progress bar") -> None:
    parser.add_argument("--quiet", action="store_true", help=what)


def controller(parser: Parser) -> None:
    parser.add_argument(
        "--controller", metavar="sp|patch|FILE.py[:Class]", help="the controller (default sp; a file: a student's)"
    )


def params_file(parser: Parser, when: str, note: str = "") -> None:
    """--params FILE.yaml: a `param dump` file's parameters, `when` they apply."""
    help = f"parameters {when}, a `param dump` file" + (f" ({note})" if note else "")
    parser.add_argument("--params", metavar="FILE.yaml", help=help)


def workspace(parser: Parser, whose: str) -> None:
    parser.add_argument(
        "--workspace",
        metavar="DIR",
        help=f"where {whose} own interface packages are "
        "(PKG/srv/X.srv, PKG/msg/X.msg, PKG/action/X.action; default: its folder and parents)",
    )


def zip_output(parser: Parser, default: str) -> None:
    parser.add_argument("-o", "--output", default=default, metavar="ZIP", help="default %(default)s")


def grade_seed(parser: Parser, help: str) -> None:
    """--seed of a grade (default $HRI_LAB_GRADE_SEED or the public seed)."""
    parser.add_argument("--seed", type=int, default=os.environ.get(GRADE_SEED_ENV, str(PUBLIC_SEED)), help=help)


def reports(parser: Parser, drawn: str) -> None:
    """The grading report's options (controllers, services, wall followers) and its seed."""
    parser.add_argument(
        "--out",
        metavar="DIR",
        help="write NAME.txt, NAME.json (and NAME.results.json with --format gradescope) per report and summary.csv",
    )
    parser.add_argument(
        "--format",
        choices=("text", "json", "gradescope"),
        default="text",
        help="what a single report prints (gradescope: its results.json); with --out, also written",
    )
    parser.add_argument("--json", metavar="OUT.json", help="also write a single report as JSON")
    grade_seed(
        parser,
        f"seed of the {drawn} (default ${GRADE_SEED_ENV} or {PUBLIC_SEED}, the public one; a course's private "
        "seed gives numbers students never saw)",
    )


def reference(parser: Parser) -> None:
    """--reference: what a file built on the lab's own controllers gets (grade, autograder)."""
    parser.add_argument(
        "--reference",
        choices=("zero", "flag"),
        default="zero",
        help="a file built on the lab's own controllers (imports, subclasses or reads sim.controllers.sp, "
        "patch, their kernels): scored 0 (zero, the default) or graded with an item that flags it (flag)",
    )


def trial_outputs(parser: Parser) -> None:
    """--record DIR, --plots DIR of `experiment` and `grade` (app/cli/outputs.py)."""
    parser.add_argument("--record", metavar="DIR", help="record every trial as MCAP in DIR (Foxglove, hri-lab play)")
    parser.add_argument(
        "--plots", metavar="DIR", help="write a figure of every trial and a summary figure to DIR (PNG, SVG)"
    )
