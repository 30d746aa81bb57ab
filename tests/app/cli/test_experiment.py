"""app/cli/experiment.py: `hri-lab experiment` — refused parameters and refused combinations exit 2
with the reason before any trial runs; a trial runs here (--jobs 1: in this process) and its JSON
carries the parameters that were changed."""

import json

import pytest

from app.cli import experiment
from app.cli.main import build_parser


def experiment_args(*words: str):
    return build_parser().parse_args(["experiment", "--quiet", "--jobs", "1", *words])


@pytest.mark.parametrize(
    ("words", "reason"),
    [
        (("--set", "alpha=7"), "alpha"),
        (("--set", "nonsense"), "NAME=VALUE"),
        (("--params", "/no/such/file.yaml"), "no such file"),
        (("--compare", "sp,patch", "--sweep", "alpha=0.3,0.5"), "--sweep runs one controller"),
    ],
)
def test_what_is_refused_exits_2_with_its_reason(words, reason, capsys):
    assert experiment.run(experiment_args(*words)) == 2
    assert reason in capsys.readouterr().err


def test_one_trial_with_a_changed_parameter(capsys):
    assert experiment.run(experiment_args("--trials", "1", "--participant", "calm", "--set", "k_t=0.2", "--json")) == 0
    report = json.loads(capsys.readouterr().out)
    assert (report["controller"], report["seed"], report["set"]) == ("sp", 0, {"k_t": 0.2})
    [trial] = report["trials"]
    assert trial["participant"] == "calm"
    assert trial["success"] is True
    assert (report["summary"]["trials"], report["summary"]["successes"]) == (1, 1)
