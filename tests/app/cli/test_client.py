"""app/cli/client.py: the ros2-like commands (service, param, action) against the real app, in this
process: the commands' own HTTP requests go to the app through FastAPI's TestClient (the same
httpx client class they make for a URL), so what they print is what a user sees."""

import argparse
import contextlib

import pytest

from app.cli import client as cli


@pytest.fixture
def hri_lab(client, monkeypatch):
    """`hri-lab ARGS...` -> (exit code, stdout, stderr), its requests answered by the test's app."""
    monkeypatch.setattr(cli, "_client", lambda args: contextlib.nullcontext(client))
    parser = argparse.ArgumentParser(prog="hri-lab")
    cli.add_parsers(parser.add_subparsers(dest="command", required=True))

    def run(*words: str) -> int:
        args = parser.parse_args(list(words))
        return cli.run(args.func, args)

    return run


def test_service_list_type_show_and_call(hri_lab, capsys):
    assert hri_lab("service", "list", "-t") == 0
    assert "/add_two_ints [hri_lab/AddTwoInts]" in capsys.readouterr().out.splitlines()
    assert hri_lab("service", "type", "add_two_ints") == 0
    assert capsys.readouterr().out == "hri_lab/AddTwoInts\n"
    assert hri_lab("service", "call", "/add_two_ints", "{a: 2, b: 40}") == 0
    out = capsys.readouterr().out
    assert "requester: making request: hri_lab.AddTwoInts_Request(a=2, b=40)" in out
    assert out.endswith("response:\nhri_lab.AddTwoInts_Response(sum=42)\n")


def test_a_failed_call_names_the_field_and_a_missing_service_says_so(hri_lab, capsys):
    assert hri_lab("service", "call", "/add_two_ints", "{a: one, b: 2}") == 1
    assert "service call failed: a: Input should be a valid integer" in capsys.readouterr().err
    assert hri_lab("service", "call", "/add_two_ints", "[1, 2]") == 1
    assert "the request must be a YAML mapping" in capsys.readouterr().err
    assert hri_lab("service", "type", "/nothing_here") == 1
    assert capsys.readouterr().err.startswith("error: service '/nothing_here' is not available")


def test_param_get_set_describe_as_ros2_prints_them(hri_lab, capsys):
    assert hri_lab("param", "get", "/cooperative_lifting", "mu") == 0
    assert capsys.readouterr().out.startswith("Double value is: ")
    assert hri_lab("param", "set", "/cooperative_lifting", "mu", "fast") == 1
    assert capsys.readouterr().out == (
        "Setting parameter failed: Wrong parameter type, parameter {mu} is of type {double}, "
        "setting it to {string} is not allowed.\n"
    )
    assert hri_lab("param", "describe", "/cooperative_lifting", "mu") == 0
    out = capsys.readouterr().out
    assert out.startswith("Parameter name: mu\n  Type: double\n")
    assert "  Constraints:\n    Min value:" in out
    assert hri_lab("param", "get", "/cooperative_lifting", "no_such") == 1


def test_param_dump_then_load_sets_each(hri_lab, capsys, tmp_path):
    assert hri_lab("param", "dump", "/cooperative_lifting") == 0
    dump = capsys.readouterr().out
    assert dump.startswith("cooperative_lifting:\n  ros__parameters:\n")
    path = tmp_path / "lifting.yaml"
    path.write_text(dump)
    assert hri_lab("param", "load", str(path)) == 0
    assert "Set parameter mu successful" in capsys.readouterr().out.splitlines()
    assert hri_lab("param", "load", str(tmp_path / "none.yaml")) == 1
    assert "none.yaml: no such file" in capsys.readouterr().err


def test_action_list_and_a_goal_to_its_end(hri_lab, capsys):
    assert hri_lab("action", "list") == 0
    assert "/count" in capsys.readouterr().out.splitlines()
    assert hri_lab("action", "send_goal", "/count", "{count: 2}", "--feedback") == 0
    out = capsys.readouterr().out
    assert out.startswith("Sending goal:\n    count: 2\n")
    assert "Goal accepted with ID: " in out
    assert out.count("Feedback:\n") >= 1
    assert out.endswith("Goal finished with status: SUCCEEDED\n")
