"""app/cli/main.py and app/cli/arguments.py: the `hri-lab` parser. Every command this module declares
shows examples under `--help`, and each example parses to that command with the values it names;
the shared arguments (--url, --seed, --jobs, --scheduler) read the same everywhere; bad values are
refused by argparse (exit 2) with the reason."""

import argparse
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from app.cli import arguments
from app.cli.main import COMMANDS, build_parser
from app.grading.report import PUBLIC_SEED

ROOT = Path(__file__).resolve().parents[3]
SHELL = (">", "|", "&", "2>")  # where an example's command ends (a redirection, a pipe, the background)


def subcommands(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    (action,) = (a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(action.choices)


def declared_here() -> list[str]:
    """The commands app/cli/main.py declares (not the client's, bag's and urdf's)."""
    sub = argparse.ArgumentParser().add_subparsers()
    for add in COMMANDS:
        add(sub)
    return list(sub.choices)


def examples(parser: argparse.ArgumentParser) -> list[list[str]]:
    """The command lines of a parser's `examples:`, as a shell splits them, up to a redirection."""
    lines = (parser.epilog or "").split("examples:\n", 1)[-1].splitlines()
    out = []
    for line in lines:
        words = shlex.split(line, comments=True)
        cut = next((i for i, w in enumerate(words) if w in SHELL), len(words))
        out.append(words[:cut])
    return out


def test_the_commands_declared_here_are_hri_labs_and_each_shows_examples():
    names = declared_here()
    assert names == [
        "experiment",
        "serve",
        "template",
        "grade",
        "grade-services",
        "grade-wall",
        "autograder",
        "handout",
        "run",
        "launch",
    ]
    parsers = subcommands(build_parser())
    for name in names:
        help_text = parsers[name].format_help()
        assert "examples:\n  hri-lab " + name in help_text, name
        assert len(examples(parsers[name])) >= 1


def test_a_command_is_declared_by_its_functions_docstring_and_arguments():
    @arguments.declared("greet")
    def greet(parser: arguments.Parser) -> None:
        """say hello to someone,
        by name

        hri-lab greet ada      # one name
        hri-lab greet ada bob
        """
        parser.add_argument("names", nargs="+")

    sub = argparse.ArgumentParser().add_subparsers()
    greet(sub)
    parser = sub.choices["greet"]
    assert sub._choices_actions[0].help == "say hello to someone, by name"  # one line in the command list
    assert parser.epilog == "examples:\n  hri-lab greet ada      # one name\n  hri-lab greet ada bob"
    assert parser.parse_args(["ada", "bob"]).names == ["ada", "bob"]


@pytest.mark.parametrize("name", declared_here())
def test_each_example_parses_to_its_command(name):
    parser = build_parser()
    for words in examples(subcommands(parser)[name]):
        assert words[:2] == ["hri-lab", name], words
        args = parser.parse_args(words[1:])
        assert args.command == name and callable(args.func), words


def test_one_commands_parser_is_the_whole_ones_part(capsys):
    """`hri-lab NAME ...` parses with NAME's parser alone (`build_parser(only=NAME)`): its help, its
    examples' values and its refusals are the whole parser's; a name that is no command is refused
    with the whole list."""
    whole = subcommands(build_parser())
    for name, parser in whole.items():
        alone = subcommands(build_parser(only=name))
        assert list(alone) == [name]
        assert alone[name].format_help() == parser.format_help(), name
        for words in examples(parser):
            expected, got = (
                vars(build_parser().parse_args(words[1:])),
                vars(build_parser(only=name).parse_args(words[1:])),
            )
            assert (got.pop("func").__qualname__, got) == (expected.pop("func").__qualname__, expected), words
    with pytest.raises(SystemExit):
        build_parser(only="experiment").parse_args(["experiment", "--participant", "nobody"])
    assert (
        "invalid choice: 'nobody' (choose from 'average', 'brisk', 'calm', 'hasty', 'tilting')"
        in capsys.readouterr().err
    )
    assert list(subcommands(build_parser(only="nosuch"))) == list(whole)


def test_a_command_line_is_parsed_by_its_commands_parser(monkeypatch, capsys):
    """main() builds the parser of the command its line names (an option first: the whole one)."""
    from app.cli import main

    built = []
    monkeypatch.setattr(main, "build_parser", lambda only=None: built.append(only) or build_parser(only))
    for words in (["run", "--help"], ["--help"]):
        with pytest.raises(SystemExit):
            main.main(words)
    assert built == ["run", None]
    assert capsys.readouterr().out.startswith("usage: hri-lab run [-h]")


def test_examples_parse_to_the_values_they_name():
    parser = build_parser()
    grade = parser.parse_args(shlex.split("grade submissions/ --out reports/ --seed 4242 --format gradescope"))
    assert (grade.controllers, grade.out, grade.seed, grade.format) == (
        ["submissions/"],
        "reports/",
        4242,
        "gradescope",
    )
    run = parser.parse_args(shlex.split("run keys_to_twist.py w --ros-args -p linear_speed:=0.25"))
    assert (run.program, run.args) == ("keys_to_twist.py", ["w", "--ros-args", "-p", "linear_speed:=0.25"])
    launch = parser.parse_args(shlex.split("launch --url http://127.0.0.1:8000 login_chain.launch user:=ada"))
    assert (launch.url, launch.file, launch.args) == ("http://127.0.0.1:8000", "login_chain.launch", ["user:=ada"])
    exp = parser.parse_args(shlex.split("experiment --sweep alpha=0.3,0.5 --sweep k_t=0.1,0.2 --set mu=0.6"))
    assert (exp.sweep, exp.set, exp.trials) == (["alpha=0.3,0.5", "k_t=0.1,0.2"], ["mu=0.6"], 9)
    template = parser.parse_args(["template"])
    assert (template.kind, template.api) == ("controller", "rospy")


def test_the_url_is_one_argument_everywhere(monkeypatch):
    """--url: $HRI_LAB_URL, else the lab `hri-lab serve` starts; launch alone starts a lab of its own."""
    monkeypatch.delenv(arguments.URL_ENV, raising=False)
    parser = build_parser()
    lines = (["grade-services"], ["run", "a.py"], ["service", "list"], ["topic", "echo", "/x"], ["record"])
    for words in lines:
        assert parser.parse_args(words).url == arguments.DEFAULT_URL, words
    assert parser.parse_args(["launch", "a.launch"]).url is None
    monkeypatch.setenv(arguments.URL_ENV, "http://lab.example:9000")
    parser = build_parser()
    for words in lines:
        assert parser.parse_args(words).url == "http://lab.example:9000", words


def test_a_grade_seed_defaults_to_the_course_seed_then_the_public_one(monkeypatch):
    monkeypatch.delenv(arguments.GRADE_SEED_ENV, raising=False)
    for words in (["grade", "f.py"], ["grade-services"], ["grade-wall", "f.py"], ["autograder"]):
        assert build_parser().parse_args(words).seed == PUBLIC_SEED, words
    monkeypatch.setenv(arguments.GRADE_SEED_ENV, "4242")
    for words in (["grade", "f.py"], ["grade-services"], ["grade-wall", "f.py"], ["autograder"]):
        assert build_parser().parse_args(words).seed == 4242, words
    assert build_parser().parse_args(["experiment"]).seed == 0  # the experiment's own seed: the same table


@pytest.mark.parametrize(
    ("words", "reason"),
    [
        (["experiment", "--jobs", "0"], "must be >= 1"),
        (["grade", "f.py", "--trials", "3"], "unrecognized arguments"),
        (["grade", "f.py", "--similarity", "1.5"], "a fraction in (0, 1]"),
        (["grade", "f.py", "--scheduler", "not an address"], "not a Dask scheduler's address"),
        (["grade", "f.py", "--only", "everything"], "invalid choice"),
        (["grade"], "the following arguments are required: FILE.py[:Class]|DIR"),
        (["serve", "--world", "moon"], "invalid choice"),
    ],
)
def test_bad_values_exit_2_naming_the_reason(words, reason, capsys):
    with pytest.raises(SystemExit) as exit:
        build_parser().parse_args(words)
    assert exit.value.code == 2
    assert reason in capsys.readouterr().err


def test_the_scheduler_and_the_jobs_read_the_same_in_every_batch_command(monkeypatch):
    monkeypatch.setenv(arguments.SCHEDULER_ENV, "tcp://10.0.0.1:8786")
    parser = build_parser()
    for words in (["experiment"], ["grade", "f.py"], ["grade-wall", "f.py"]):
        args = parser.parse_args([*words, "--jobs", "3"])
        assert (args.scheduler, args.jobs) == ("tcp://10.0.0.1:8786", 3), words
    assert parser.parse_args(["grade", "f.py", "--scheduler", ""]).scheduler is None


def test_a_closed_stdout_ends_the_command_quietly_as_sigpipe_would():
    """`hri-lab topic echo ... | head`: once the reader has gone, the command ends with 141 and no
    traceback (its printing fails with BrokenPipeError, here raised by the command itself)."""
    program = (
        "import sys\n"
        "from app.cli import client, main\n"
        "def closed(func, args):\n"
        "    raise BrokenPipeError(32, 'Broken pipe')\n"
        "client.run = closed\n"
        "sys.exit(main.main(['topic', 'list']))\n"
    )
    done = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert (done.returncode, done.stderr) == (141, "")


def test_run_and_launch_start_without_httpx():
    """`hri-lab run` and `launch` send no request before they hand over to the program: their start
    does not import httpx (with its own command line's rich, click and pygments, half a CLI start's
    CPU; each program a test runs pays it), which the client's commands import when they send one;
    nor websockets, yaml or the cluster's runner, which the commands that use them import (every
    command builds the parser: docs/performance.md, "The commands' start")."""
    program = (
        "import sys\n"
        "from app.cli.main import build_parser\n"
        "build_parser().parse_args(['run', 'talker.py'])\n"
        "build_parser().parse_args(['launch', 'calculator.launch.xml'])\n"
        "heavy = ('httpx', 'rich', 'click', 'pygments', 'websockets', 'yaml', 'sim.procedures.runner', 'multiprocessing')\n"
        "print(sorted(m for m in heavy if m in sys.modules))\n"
    )
    done = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert done.stdout.strip() == "[]", done.stdout + done.stderr
