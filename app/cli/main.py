"""`hri-lab` command line: every command's arguments, and the dispatch.

A command is declared by one small function here (`arguments.declared`: its arguments, the shared
ones from app/cli/arguments.py, each declared once; its docstring, the command's help and its
examples, which `--help` prints); its code is its own module (`app/cli/experiment.py`, `serve.py`,
`grade.py`, ...), imported when that command runs (`arguments.runs`): the ros2-like client commands
start without loading the simulation (numba, pinocchio) that `experiment`, `grade` and `serve` need.
"""

from __future__ import annotations

import argparse
import functools
import os
import signal
import sys
from collections.abc import Callable, Iterable, Sequence
from typing import Any, overload

from app.cli import arguments as a
from app.cli import bag
from app.cli import client as client_cli
from app.cli import urdf as urdf_cli
from app.grading.report import PUBLIC_SEED

SECTIONS = ("probe", "trial", "robustness")  # the parts of the grading battery (app/grading/battery.py)


@a.declared("experiment")
def _experiment(exp: a.Parser) -> None:
    """run the lab's Table 1 trials headless (faster than real time)

    hri-lab experiment                              # the nine trials, one table
    hri-lab experiment --compare sp,patch --seed 3  # the same trials with each controller
    hri-lab experiment --sweep alpha=0.3,0.5,0.8 --participant hasty --plots figures/
    """
    exp.add_argument(
        "--trials", type=a.positive_int, default=9, help="number of trials (default 9 = 3 participants x 3 tries)"
    )
    exp.add_argument("--participant", choices=Choices(_participants), help="only this participant")
    exp.add_argument("--seed", type=int, default=0, help="random seed (same seed, same table)")
    a.jobs(exp, "trials")
    exp.add_argument("--json", action="store_true", help="print JSON instead of the table")
    a.controller(exp)
    exp.add_argument(
        "--compare", metavar="sp,patch", help="run the same participants and seeds with each controller, side by side"
    )
    exp.add_argument(
        "--set",
        action="append",
        metavar="NAME=VALUE",
        help="a parameter for every trial, e.g. --set alpha=0.5 --set k_t=0.2 (checked like `param set`)",
    )
    a.params_file(exp, "for every trial", "--set wins")
    exp.add_argument(
        "--sweep",
        action="append",
        metavar="NAME=V1,V2,...",
        help="run the same trials at each value (twice: a grid of two parameters); one table",
    )
    a.quiet(exp)
    a.scheduler(exp, "every trial (and sweep point)")
    a.trial_outputs(exp)
    exp.set_defaults(func=a.runs("app.cli.experiment"))


@a.declared("serve")
def _serve(srv: a.Parser) -> None:
    """start the lab's server (HTTP API on 127.0.0.1)

    hri-lab serve                      # the lab at http://127.0.0.1:8000, its 3D view at :8080
    hri-lab serve --exercises --view light
    hri-lab serve --world mobile --arena-seed 7
    """
    srv.add_argument("--host", default="127.0.0.1", help="address to bind (default 127.0.0.1: this machine only)")
    srv.add_argument("--port", type=int, default=8000)
    a.params_file(srv, "to load at start")
    srv.add_argument(
        "--view",
        choices=("full", "light", "none"),
        default=os.environ.get("HRI_LAB_VIEW", "full"),
        help="3D view: full meshes, light (collision meshes, no shadows: software-rendered browsers) or none",
    )
    srv.add_argument(
        "--view-port", type=int, default=8080, help="port of the 3D view (viser moves to the next free one)"
    )
    a.controller(srv)
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
        "--no-token",
        action="store_true",
        help="bind --host without a token: only inside a container whose port the host publishes on its own "
        "loopback (docker run -p 127.0.0.1:8000:8000; the container image's default command)",
    )
    srv.add_argument(
        "--exercises",
        action="store_true",
        help="leave the handout's exercise services to the students' nodes (rosbridge): "
        "each answers 'not provided yet' until a node advertises it",
    )
    srv.add_argument(
        "--world",
        choices=Choices(_worlds),
        metavar="WORLD",  # argparse would read the choices to draw {a,b} as the parser is built
        default=None,
        help="the world served, one of %(choices)s (default: the first, the Panda and the box; "
        "the mobile one, a TurtleBot3-like base in an arena: docs/mobile-lab.md)",
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
    srv.set_defaults(func=a.runs("app.cli.serve"))


@a.declared("template")
def _template(tpl: a.Parser) -> None:
    """print a starting file: the controller (default), a services node or the lifting node

    hri-lab template > cooperative_lifting.py
    hri-lab template services --api rclpy > services_rclpy.py
    hri-lab template node --api roslibpy > lifting_node.py
    """
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
    tpl.set_defaults(func=_print_template)


@a.declared("grade")
def _grade(grd: a.Parser) -> None:
    """grade students' controller files (probes, the nine trials, robustness), sandboxed

    hri-lab grade cooperative_lifting.py                 # one file, its report
    hri-lab grade submissions/ --out reports/ --seed 4242 --format gradescope
    hri-lab grade cooperative_lifting.py --only probe    # a quick check, not a grade
    """
    grd.add_argument(
        "controllers", nargs="+", metavar="FILE.py[:Class]|DIR", help="files, or folders of .py files (a batch)"
    )
    a.reports(grd, "probe values and trials")
    a.jobs(grd, "items")
    a.unsandboxed(grd, "files")
    a.quiet(grd)
    a.reference(grd)
    grd.add_argument(
        "--similarity",
        type=a.fraction,
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
    a.scheduler(grd, "every item of every file")
    a.trial_outputs(grd)
    grd.set_defaults(func=a.runs("app.cli.grade"))


@a.declared("grade-services")
def _grade_services(gsv: a.Parser) -> None:
    """grade the handout's exercise services a student's node provides (a lab started with serve --exercises), over its
    HTTP API

    hri-lab grade-services                                  # the lab at $HRI_LAB_URL
    hri-lab grade-services --url http://127.0.0.1:8001 --seed 4242 --out reports/
    """
    a.url(gsv)
    a.reports(gsv, "cases")
    a.quiet(gsv, "no progress lines")
    gsv.set_defaults(func=a.runs("app.cli.grade_services"))


@a.declared("grade-wall")
def _grade_wall(gwl: a.Parser) -> None:
    """grade wall followers (rospy/rclpy programs: /scan in, /cmd_vel out) in the mobile world's trials

    hri-lab grade-wall follower.py --seed 4711 --trials 5
    hri-lab grade-wall submissions/ --out reports/ --format gradescope
    """
    gwl.add_argument("programs", nargs="+", metavar="FOLLOWER.py|DIR", help="files, or folders of .py files (a batch)")
    a.reports(gwl, "trials (obstacle, start pose, noise)")
    gwl.add_argument("--trials", type=a.positive_int, help="trials per file (default 3)")
    a.jobs(gwl, "trials")
    a.unsandboxed(gwl, "programs")
    a.quiet(gwl)
    a.scheduler(gwl, "every trial of every file")
    gwl.set_defaults(func=a.runs("app.cli.grade_wall"))


@a.declared("autograder")
def _autograder(agr: a.Parser) -> None:
    """write a Gradescope autograder bundle (setup.sh, run_autograder) that grades with this lab

    hri-lab autograder --seed 4242 -o autograder.zip
    hri-lab autograder --public-seed --services       # a trial run, services graded too
    """
    a.zip_output(agr, "autograder.zip")
    a.grade_seed(
        agr,
        f"the course's private seed of the probe values and trials (default ${a.GRADE_SEED_ENV}; the public "
        f"default {PUBLIC_SEED}, which every student can grade with at home, is refused without --public-seed)",
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
    a.reference(agr)
    agr.set_defaults(func=a.runs("app.cli.autograder"))


@a.declared("handout")
def _handout(hnd: a.Parser) -> None:
    """write the lab as students get it: the lab, its examples and docs, no tests/ (the filled templates, the
    reference) and no bench/

    hri-lab handout -o hri-lab-students.zip --folder hri-lab-2026
    """
    a.zip_output(hnd, "hri-lab-students.zip")
    hnd.add_argument("--folder", default="hri-lab", help="the folder in the zip (default %(default)s)")
    hnd.set_defaults(func=a.runs("app.cli.handout"))


@a.declared("run")
def _run(run: a.Parser) -> None:
    """run a ROS program (rospy, rclpy) against the lab, like rosrun / ros2 run

    hri-lab run add_two_ints_client.py 20 22
    hri-lab run learning_service service_adder_server     # a package's executable, as ros2 run
    hri-lab run keys_to_twist.py w --ros-args -p linear_speed:=0.25
    hri-lab run --workspace ~/catkin_ws/src calculator_server.py
    """
    a.url(run)
    a.workspace(run, "the program's")
    run.add_argument("program", metavar="FILE.py|PKG", help="a program file, or a package (then its executable EXE)")
    run.add_argument("args", nargs=argparse.REMAINDER, help="the program's arguments (and --ros-args ...)")
    run.set_defaults(func=a.runs("rosclient.run"))


@a.declared("launch")
def _launch(lch: a.Parser) -> None:
    """start the lab and the nodes of a launch file: roslaunch XML, ROS 2 XML, YAML or Python

    hri-lab launch calculator.launch.xml                # its own lab and the nodes
    hri-lab launch lab8 lab8.launch.py offset:=10       # a package's launch file, as ros2 launch
    hri-lab launch --url http://127.0.0.1:8000 login_chain.launch user:=ada
    """
    a.url(lch, "a running lab (default: start one, like roslaunch starts roscore)", start_one=True)
    a.workspace(lch, "the programs'")
    lch.add_argument("file", metavar="FILE|PKG", help="a launch file, or a package (then its launch file's name)")
    lch.add_argument("args", nargs="*", metavar="NAME:=VALUE", help="the launch file's arguments")
    lch.set_defaults(func=a.runs("app.cli.launch_nodes"))


COMMANDS = (_experiment, _serve, _template, _grade, _grade_services, _grade_wall, _autograder, _handout, _run, _launch)


class Choices(Sequence[str]):
    """An argument's choices read when argparse first asks for them (at a command line naming that
    command): the modules that hold them are slow to import, not for every command."""

    def __init__(self, names: Callable[[], Iterable[str]]) -> None:
        self._load = names

    @functools.cached_property
    def _names(self) -> list[str]:
        return list(self._load())

    @overload
    def __getitem__(self, index: int) -> str: ...

    @overload
    def __getitem__(self, index: slice) -> Sequence[str]: ...

    def __getitem__(self, index: int | slice) -> str | Sequence[str]:
        return self._names[index]

    def __len__(self) -> int:
        return len(self._names)


def _worlds() -> Iterable[str]:
    from app.serving.worlds import WORLDS  # a world's package: the simulation's

    return WORLDS


def _participants() -> Iterable[str]:
    from sim.person.participants import PARTICIPANTS  # the simulation's package (its kernels' caches checked)

    return sorted(PARTICIPANTS)


class _Unread:
    """A command's parser when another command runs: takes what the command's declaration adds to it
    (arguments, groups, sub-commands, defaults) and keeps nothing."""

    def __getattr__(self, _name: str) -> Callable[..., _Unread]:
        return self._take

    def _take(self, *_args: object, **_kwargs: object) -> _Unread:
        return self


class _Only:
    """The sub-commands of `hri-lab` that add the parser of `name` alone (`build_parser(only=...)`)."""

    def __init__(self, sub: argparse._SubParsersAction, name: str) -> None:
        self.sub, self.name = sub, name

    def add_parser(self, name: str, **kwargs: Any) -> argparse.ArgumentParser | _Unread:
        return self.sub.add_parser(name, **kwargs) if name == self.name else _Unread()


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """`hri-lab`: this module's commands, then the ros2-like client's, bag's and urdf's. With `only`
    (the command a command line names), that command's parser alone, which parses its command
    lines as the whole one does: argparse looks its messages up with gettext for every parser
    (half a millisecond each, 51 parsers: a quarter of a client command's start, every `hri-lab
    run` of a student's program). A name that is no command gets the whole parser (its error lists
    them all)."""
    parser = argparse.ArgumentParser(prog="hri-lab", description="The simulated cooperative-lifting lab.")
    sub = parser.add_subparsers(dest="command", required=True)
    adding: Any = sub if only is None else _Only(sub, only)
    for add in COMMANDS:
        add(adding)
    client_cli.add_parsers(adding)
    bag.add_parsers(adding)
    urdf_cli.add_parsers(adding)
    if only is not None and only not in sub.choices:
        return build_parser()
    return parser


def _print_template(args: argparse.Namespace) -> int:
    from app.cli.templates import render

    print(render(args.kind, args.api), end="")
    return 0


def _stop_with_workers(signum, frame) -> None:
    """SIGTERM/SIGHUP: the trial workers (experiment, grade --jobs) go with this process (none
    when the command has not imported multiprocessing; nothing is imported in a signal handler)."""
    multiprocessing = sys.modules.get("multiprocessing")
    for child in multiprocessing.active_children() if multiprocessing else ():
        child.kill()
    os._exit(128 + signum)


def main(argv: list[str] | None = None) -> int:
    words = sys.argv[1:] if argv is None else argv
    args = build_parser(only=words[0] if words and not words[0].startswith("-") else None).parse_args(words)
    if args.command in ("experiment", "grade"):
        for signum in (signal.SIGTERM, signal.SIGHUP):
            signal.signal(signum, _stop_with_workers)
    try:
        return client_cli.run(args.func, args)
    except BrokenPipeError:  # e.g. `hri-lab topic echo ... | head`: the reader has what it wanted
        # Python's advice for a closed stdout: nothing more goes to it, not even at exit's flush
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 128 + signal.SIGPIPE
