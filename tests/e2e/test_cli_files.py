"""A file handed to a command that is not what the command reads is refused with what it is not and
what to do, and a non-zero exit: recordings (`bag info`, `play`), parameter files (`param load`,
`experiment --params`, `serve --params`), controller files (`--controller`, `grade`)."""

import json
import os

import pytest
from mcap.writer import Writer

from sim.recording import reader

from app.cli import client as client_cli
from app.cli.main import build_parser

RANDOM = bytes(range(256)) * 8 + os.urandom(2048)  # invalid UTF-8 for sure (0x80.. after 0x00..)
TEXT = "time,force\n0.0,10.2\n0.1,10.4\n"


@pytest.fixture
def files(tmp_path):
    paths = {
        "random": tmp_path / "random.mcap",
        "text": tmp_path / "notes.mcap",
        "empty": tmp_path / "empty.mcap",
        "folder": tmp_path / "folder",
    }
    paths["random"].write_bytes(RANDOM)
    paths["text"].write_text(TEXT)
    paths["empty"].write_bytes(b"")
    paths["folder"].mkdir()
    return paths


def cli(*argv: str) -> int:
    """The `hri-lab` command in this process (its dispatch and error printing, not main()'s signal handlers)."""
    args = build_parser().parse_args(list(argv))
    return client_cli.run(args.func, args)


@pytest.mark.parametrize(
    ("kind", "what"),
    [
        ("random", "a binary file of another format"),
        ("text", "a text file"),
        ("empty", "an empty file"),
        ("folder", "a folder"),
    ],
)
@pytest.mark.parametrize("command", [("bag", "info"), ("play",)])
def test_a_file_that_is_not_mcap_is_named_and_the_exit_is_non_zero(files, kind, what, command, capsys):
    code = cli(*command, str(files[kind]))
    out, err = capsys.readouterr()
    assert code == 1
    assert "not an MCAP recording" in err
    assert what in err
    assert "Messages:" not in out  # no summary of 0 messages, no 1970 start
    if kind != "folder":
        assert "hri-lab record" in err  # what to do


def test_a_file_cut_short_after_the_magic_is_still_a_recording(tmp_path, capsys):
    """The check looks at MCAP's magic bytes only: a recording whose writer died is still read."""
    path = tmp_path / "cut.mcap"
    path.write_bytes(reader.MCAP_MAGIC)
    assert cli("bag", "info", str(path)) == 0
    assert "cut short" in capsys.readouterr().out


def test_play_names_an_mcap_file_that_another_tool_wrote(tmp_path, capsys):
    """A real MCAP file with JSON that is not the lab's: play says it is not a hri-lab recording."""
    path = tmp_path / "other.mcap"
    with open(path, "wb") as f:
        writer = Writer(f)
        writer.start()
        schema = writer.register_schema("other/Thing", "jsonschema", b"{}")
        for topic in ("/tf", "/scene", "/joint_states"):
            channel = writer.register_channel(topic, "json", schema)
            writer.add_message(channel, log_time=1, publish_time=1, data=json.dumps({"x": 1}).encode())
        writer.finish()
    assert cli("bag", "info", str(path)) == 0  # a good MCAP file: info reads it
    capsys.readouterr()
    assert cli("play", str(path)) == 1
    assert "not a hri-lab recording" in capsys.readouterr().err


def test_param_load_names_a_file_that_is_not_a_parameter_file(files, tmp_path, capsys):
    """Refused before any server is asked (the URL below has none)."""
    url = ("--url", "http://127.0.0.1:9")
    assert cli("param", "load", str(files["random"]), *url) == 1
    assert "not a parameter file (binary, not UTF-8 text" in capsys.readouterr().err
    assert cli("param", "load", str(tmp_path / "missing.yaml"), *url) == 1
    assert "missing.yaml: no such file" in capsys.readouterr().err
    assert cli("param", "load", str(files["folder"]), *url) == 1
    assert "a folder, not a parameter file" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("content", "reason"),
    [
        (RANDOM, "not a parameter file (binary, not UTF-8 text"),
        (TEXT.encode(), "maps node names to {ros__parameters: {...}}, as `hri-lab param dump` writes it"),
        (b"x: " + b"[" * 40 + b"]" * 40, "nests at most 16 levels"),  # the server's limits, headless too
    ],
)
def test_experiment_params_names_a_file_that_is_not_a_parameter_file(tmp_path, content, reason, capsys):
    path = tmp_path / "lab.yaml"
    path.write_bytes(content)
    assert cli("experiment", "--params", str(path), "--trials", "1", "--quiet") == 2
    err = capsys.readouterr().err
    assert f"{path}: " in err
    assert reason in err


def test_serve_params_names_a_binary_file_and_does_not_start(files, capsys):
    assert cli("serve", "--params", str(files["random"]), "--view", "none", "--port", "0") == 2
    err = capsys.readouterr().err
    assert f"cannot load parameters from {files['random']}: not a parameter file (binary" in err


@pytest.mark.parametrize(
    ("kind", "reason"),
    [("random", "is not a Python file (binary, not source text)"), ("folder", "is a folder, not a controller file")],
)
def test_a_controller_that_is_not_a_python_file_is_named(files, kind, reason, capsys):
    with pytest.raises(SystemExit) as stop:
        cli("experiment", "--controller", str(files[kind]), "--trials", "1", "--quiet")
    assert stop.value.code == 2
    assert reason in capsys.readouterr().err


def test_grade_reports_a_binary_file_as_not_graded(files, tmp_path, capsys):
    code = cli("grade", str(files["random"]), "--quiet", "--jobs", "1", "--out", str(tmp_path / "reports"))
    out = capsys.readouterr().out
    assert code == 1
    assert "NOT GRADED" in out
    assert "is not a Python file (binary, not source text)" in out
