"""`hri-lab` command line: every command's arguments, and the dispatch.

A command's code is its own module (`app/cli/experiment.py`, `serve.py`, `grade.py`, ...), imported
when that command runs (`_command`): the ros2-like client commands start without loading the
simulation (numba, pinocchio) that `experiment`, `grade` and `serve` need.
"""

from __future__ import annotations

import argparse
import importlib
import multiprocessing
import os
import re
import signal
import sys

from sim.person.participants import PARTICIPANTS
from sim.procedures.report import PUBLIC_SEED

from app.cli import bag
from app.cli import client as client_cli
from app.cli import urdf as urdf_cli

SECTIONS = ("probe", "trial", "robustness")  # the parts of the grading battery (sim/procedures/grading.py's battery)


def _fraction(text: str) -> float:
    value = float(text)
    if not 0.0 < value <= 1.0:
        raise argparse.ArgumentTypeError(f"a fraction in (0, 1], got {text}")
    return value


def _reference_option(parser: argparse.ArgumentParser) -> None:
    """--reference: what a file built on the lab's own controllers gets (grade, autograder)."""
    parser.add_argument(
        "--reference",
        choices=("zero", "flag"),
        default="zero",
        help="a file built on the lab's own controllers (imports, subclasses or reads sim.controllers.sp, "
        "patch, their kernels): scored 0 (zero, the default) or graded with an item that flags it (flag)",
    )


def _command(module: str):
    """The command `module.run(args)`, its module imported when the command runs."""

    def run(args: argparse.Namespace) -> int:
        from sim.procedures.runner import ClusterUnreachable

        try:
            return importlib.import_module(module).run(args)
        except ClusterUnreachable as exc:  # --scheduler names no cluster: one line, exit 1
            print(f"hri-lab {args.command}: {exc}", file=sys.stderr)
            return 1

    return run


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="hri-lab", description="The simulated cooperative-lifting lab.")
    sub = parser.add_subparsers(dest="command", required=True)
    exp = sub.add_parser("experiment", help="run the lab's Table 1 trials headless (faster than real time)")
    exp.add_argument(
        "--trials", type=_positive_int, default=9, help="number of trials (default 9 = 3 participants x 3 tries)"
    )
    exp.add_argument("--participant", choices=sorted(PARTICIPANTS), help="only this participant")
    exp.add_argument("--seed", type=int, default=0, help="random seed (same seed, same table)")
    exp.add_argument(
        "--jobs",
        type=_positive_int,
        default=os.cpu_count() or 1,
        help="trials run in this many processes (default: one per core; same results)",
    )
    exp.add_argument("--json", action="store_true", help="print JSON instead of the table")
    exp.add_argument(
        "--controller", metavar="sp|patch|FILE.py[:Class]", help="the controller (default sp; a file: a student's)"
    )
    exp.add_argument(
        "--compare", metavar="sp,patch", help="run the same participants and seeds with each controller, side by side"
    )
    exp.add_argument(
        "--set",
        action="append",
        metavar="NAME=VALUE",
        help="a parameter for every trial, e.g. --set alpha=0.5 --set k_t=0.2 (checked like `param set`)",
    )
    exp.add_argument(
        "--params", metavar="FILE.yaml", help="parameters for every trial, a `param dump` file (--set wins)"
    )
    exp.add_argument(
        "--sweep",
        action="append",
        metavar="NAME=V1,V2,...",
        help="run the same trials at each value (twice: a grid of two parameters); one table",
    )
    exp.add_argument("--quiet", action="store_true", help="no progress bar")
    _scheduler_option(exp, "every trial (and sweep point)")
    add_output_options(exp)
    exp.set_defaults(func=_command("app.cli.experiment"))

    srv = sub.add_parser("serve", help="start the lab's server (HTTP API on 127.0.0.1)")
    srv.add_argument("--host", default="127.0.0.1", help="address to bind (default 127.0.0.1: this machine only)")
    srv.add_argument("--port", type=int, default=8000)
    srv.add_argument("--params", metavar="FILE.yaml", help="parameters to load at start (a `param dump` file)")
    srv.add_argument(
        "--view",
        choices=("full", "light", "none"),
        default=os.environ.get("HRI_LAB_VIEW", "full"),
        help="3D view: full meshes, light (collision meshes, no shadows: software-rendered browsers) or none",
    )
    srv.add_argument(
        "--view-port", type=int, default=8080, help="port of the 3D view (viser moves to the next free one)"
    )
    srv.add_argument(
        "--controller", metavar="sp|patch|FILE.py[:Class]", help="the controller (default sp; a file: a student's)"
    )
    srv.add_argument(
        "--output-dir",
        default=".",
        metavar="DIR",
        help="where live recordings (DIR/recordings) and the actions' figures (DIR/figures) go",
    )
    srv.add_argument(
        "--token",
        default=os.environ.get("HRI_LAB_TOKEN"),
        help="token that changes must carry (required to bind other than 127.0.0.1; default $HRI_LAB_TOKEN)",
    )
    srv.add_argument(
        "--exercises",
        action="store_true",
        help="leave the handout's exercise services to the students' nodes (rosbridge): "
        "each answers 'not provided yet' until a node advertises it",
    )
    srv.add_argument(
        "--world",
        choices=("lifting", "mobile"),
        default="lifting",
        help="lifting: the Panda and the box (default); mobile: a TurtleBot3-like base in an arena (docs/mobile-lab.md)",
    )
    srv.add_argument(
        "--arena-seed",
        type=int,
        default=None,
        metavar="N",
        help="--world mobile: the arena, the start pose and the noise this seed draws (default: the standard arena)",
    )
    srv.add_argument(
        "--replay",
        action="store_true",
        help="a lab to play bags into: its simulation publishes no topic over rosbridge, so `hri-lab bag play` "
        "publishes every recorded topic (/joint_states, /image_raw ...) as the robot would",
    )
    srv.set_defaults(func=_command("app.cli.serve"))

    tpl = sub.add_parser(
        "template", help="print a starting file: the controller (default), a services node or the lifting node"
    )
    tpl.add_argument(
        "kind",
        nargs="?",
        choices=("controller", "services", "node"),
        default="controller",
        help="controller: cooperative_lifting.py (plug-in); services: a node with the handout's "
        "servers; node: the lifting application as a node",
    )
    tpl.add_argument(
        "--api",
        choices=("rospy", "rclpy", "roslibpy"),
        default="rospy",
        help="the node's client library (default rospy, like the handout; rospy and rclpy programs "
        "run with `hri-lab run`)",
    )
    tpl.set_defaults(func=_template)

    grd = sub.add_parser(
        "grade", help="grade students' controller files (probes, the nine trials, robustness), sandboxed"
    )
    grd.add_argument(
        "controllers", nargs="+", metavar="FILE.py[:Class]|DIR", help="files, or folders of .py files (a batch)"
    )
    _report_options(grd, "probe values and trials")
    grd.add_argument("--jobs", type=_positive_int, default=os.cpu_count() or 1, help="items in parallel processes")
    grd.add_argument(
        "--unsandboxed",
        action="store_true",
        help="run the files without bubblewrap (still in processes of their own) where bwrap cannot run",
    )
    grd.add_argument("--quiet", action="store_true", help="no progress bar")
    _reference_option(grd)
    grd.add_argument(
        "--similarity",
        type=_fraction,
        metavar="FRACTION",
        help="with --out: flag a pair of files (or a file and the lab's controllers) when either has this share "
        "of its code in the other (similarity.csv, similarity.html; default: similarity.THRESHOLD, a half)",
    )
    grd.add_argument(
        "--only",
        action="append",
        choices=SECTIONS,
        metavar="|".join(SECTIONS),
        help="grade only this part of the battery (again for another; default all): a quick check, not a grade",
    )
    grd.add_argument(
        "--force",
        action="store_true",
        help="with --out: grade every file again (default: skip a file whose report there is for the same seed and file)",
    )
    _scheduler_option(grd, "every item of every file")
    add_output_options(grd)
    grd.set_defaults(func=_command("app.cli.grade"))

    gsv = sub.add_parser(
        "grade-services",
        help="grade the handout's exercise services a student's node provides "
        "(a lab started with serve --exercises), over its HTTP API",
    )
    gsv.add_argument(
        "--url",
        default=os.environ.get("HRI_LAB_URL", client_cli.DEFAULT_URL),
        help="the lab (default $HRI_LAB_URL or %(default)s); changes carry $HRI_LAB_TOKEN",
    )
    _report_options(gsv, "cases")
    gsv.add_argument("--quiet", action="store_true", help="no progress lines")
    gsv.set_defaults(func=_command("app.cli.grade_services"))

    gwl = sub.add_parser(
        "grade-wall",
        help="grade wall followers (rospy/rclpy programs: /scan in, /cmd_vel out) in the mobile world's trials",
    )
    gwl.add_argument("programs", nargs="+", metavar="FOLLOWER.py|DIR", help="files, or folders of .py files (a batch)")
    _report_options(gwl, "trials (obstacle, start pose, noise)")
    gwl.add_argument("--trials", type=_positive_int, help="trials per file (default 3)")
    gwl.add_argument("--jobs", type=_positive_int, default=os.cpu_count() or 1, help="trials in parallel processes")
    gwl.add_argument("--quiet", action="store_true", help="no progress bar")
    _scheduler_option(gwl, "every trial of every file")
    gwl.set_defaults(func=_command("app.cli.grade_wall"))

    agr = sub.add_parser(
        "autograder", help="write a Gradescope autograder bundle (setup.sh, run_autograder) that grades with this lab"
    )
    agr.add_argument("-o", "--output", default="autograder.zip", metavar="ZIP", help="default %(default)s")
    agr.add_argument(
        "--seed",
        type=int,
        default=os.environ.get("HRI_LAB_GRADE_SEED", str(PUBLIC_SEED)),
        help="the course's private seed of the probe values and trials (default $HRI_LAB_GRADE_SEED; "
        f"the public default {PUBLIC_SEED}, which every student can grade with at home, is refused "
        "without --public-seed)",
    )
    agr.add_argument(
        "--public-seed",
        action="store_true",
        help=f"accept the public default seed {PUBLIC_SEED} (a trial run, not a course's grades)",
    )
    agr.add_argument(
        "--services",
        action="store_true",
        help="also grade the services exercises of the submission's services_node.py (a lab started in the container)",
    )
    agr.add_argument(
        "--hide-until-due",
        action="store_true",
        help="show the tests (their seed-drawn numbers) only after the due date; the score at once",
    )
    _reference_option(agr)
    agr.set_defaults(func=_command("app.cli.autograder"))

    hnd = sub.add_parser(
        "handout",
        help="write the lab as students get it: the lab, its examples and docs, no tests/ (the filled templates, "
        "the reference) and no bench/",
    )
    hnd.add_argument("-o", "--output", default="hri-lab-students.zip", metavar="ZIP", help="default %(default)s")
    hnd.add_argument("--folder", default="hri-lab", help="the folder in the zip (default %(default)s)")
    hnd.set_defaults(func=_command("app.cli.handout"))

    run = sub.add_parser("run", help="run a ROS program (rospy, rclpy) against the lab, like rosrun / ros2 run")
    run.add_argument(
        "--url",
        default=os.environ.get("HRI_LAB_URL", client_cli.DEFAULT_URL),
        help="the lab (default $HRI_LAB_URL or %(default)s); changes carry $HRI_LAB_TOKEN",
    )
    run.add_argument(
        "--workspace",
        metavar="DIR",
        help="where the program's own interface packages are "
        "(PKG/srv/X.srv, PKG/msg/X.msg, PKG/action/X.action; default: its folder and parents)",
    )
    run.add_argument("program", metavar="FILE.py")
    run.add_argument("args", nargs=argparse.REMAINDER, help="the program's arguments (and --ros-args ...)")
    run.set_defaults(func=_command("app.rosclient.run"))

    lch = sub.add_parser("launch", help="start the lab and the nodes of a roslaunch / ROS 2 XML launch file")
    lch.add_argument("--url", help="a running lab (default: start one, like roslaunch starts roscore)")
    lch.add_argument("--workspace", metavar="DIR", help="where the programs' own interface packages are")
    lch.add_argument("file", metavar="FILE.launch|FILE.launch.xml")
    lch.add_argument("args", nargs="*", metavar="NAME:=VALUE", help="the launch file's arguments")
    lch.set_defaults(func=_command("app.rosclient.launch"))

    client_cli.add_parsers(sub)
    bag.add_parsers(sub)
    urdf_cli.add_parsers(sub)
    return parser


def add_output_options(parser: argparse.ArgumentParser) -> None:
    """--record DIR, --plots DIR of `experiment` and `grade` (app/cli/outputs.py)."""
    parser.add_argument("--record", metavar="DIR", help="record every trial as MCAP in DIR (Foxglove, hri-lab play)")
    parser.add_argument(
        "--plots", metavar="DIR", help="write a figure of every trial and a summary figure to DIR (PNG, SVG)"
    )


def _scheduler_option(parser: argparse.ArgumentParser, what: str) -> None:
    """--scheduler: a Dask cluster instead of --jobs (docs/course-scale.md)."""
    parser.add_argument(
        "--scheduler",
        metavar="tcp://HOST:8786",
        type=_scheduler_address,
        default=os.environ.get("HRI_LAB_SCHEDULER"),
        help=f"run {what} as a task on this Dask cluster instead of --jobs processes here "
        "(default $HRI_LAB_SCHEDULER; the same results)",
    )


def _report_options(parser: argparse.ArgumentParser, drawn: str) -> None:
    """The grading report's options (the same for controllers and services)."""
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
    parser.add_argument(
        "--seed",
        type=int,
        default=os.environ.get("HRI_LAB_GRADE_SEED", str(PUBLIC_SEED)),
        help=f"seed of the {drawn} "
        f"(default $HRI_LAB_GRADE_SEED or {PUBLIC_SEED}, the public one; a course's private seed gives numbers "
        "students never saw)",
    )


def _template(args: argparse.Namespace) -> int:
    from app.cli.templates import render

    print(render(args.kind, args.api), end="")
    return 0


def _scheduler_address(text: str) -> str | None:
    """A Dask scheduler's address: [tcp|tls://]HOST:PORT ("" = none)."""
    if not text:
        return None
    if not re.fullmatch(r"((tcp|tls)://)?[A-Za-z0-9._\-\[\]:]+:\d{1,5}", text):
        raise argparse.ArgumentTypeError(f"{text!r} is not a Dask scheduler's address, e.g. tcp://HOST:8786")
    return text


def _positive_int(text: str) -> int:
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError("must be >= 1")
    return value


def _stop_with_workers(signum, frame) -> None:
    """SIGTERM/SIGHUP: the trial workers (experiment, grade --jobs) go with this process."""

    for child in multiprocessing.active_children():
        child.kill()
    os._exit(128 + signum)


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    if args.command in ("experiment", "grade"):
        for signum in (signal.SIGTERM, signal.SIGHUP):
            signal.signal(signum, _stop_with_workers)
    return client_cli.run(args.func, args)
