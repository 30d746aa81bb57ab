"""`hri-lab experiment` as a user runs it: one trial's JSON and table, a comparison of two
controllers on the same participants and seeds, a refused argument. (The trials themselves:
tests/sim/test_world.py; parameters: tests/e2e/test_experiment_params.py.)"""

import json

from sim.controllers.interface import LiftingParams
from sim.procedures.experiment import plan
from sim.procedures.tables import format_comparison
from sim.procedures.trial import TrialResult

from tests.lab_zygote import run_command

# the short trial: at the wider margin alpha 0.8 the hasty participant's box is dropped at ~3 s
SHORT = ("--trials", "1", "--participant", "hasty", "--seed", "3", "--set", "alpha=0.8")


def experiment(*args: str) -> str:
    """`hri-lab experiment ARGS`'s output; fails the test when it exits non-zero."""
    run = run_command("experiment", *args, timeout=300)
    assert run.returncode == 0, run.stderr
    return run.stdout


def test_cli_experiment_json():
    data = json.loads(experiment(*SHORT, "--json", "--quiet"))
    assert data["summary"]["trials"] == 1
    trial = data["trials"][0]
    assert set(trial) >= {"success", "duration", "f_n_min", "f_n_max", "max_friction_ratio", "slip", "reason"}
    table = experiment(*SHORT, "--quiet")
    assert "participant" in table
    assert "hasty" in table
    assert "success: " in table
    bad = run_command("experiment", "--trials", "0", timeout=120)
    assert bad.returncode == 2
    assert "--trials" in bad.stderr


def test_cli_compare_runs_the_same_participants_and_seeds_with_each_controller():
    data = json.loads(experiment("--compare", "sp,patch", *SHORT, "--json", "--jobs", "2"))
    title_asked = f"seed 3; parameters: alpha = 0.8 (default {LiftingParams().alpha:g})"
    assert data["set"] == {"alpha": 0.8}
    assert data["seed"] == 3
    data = data["results"]
    assert list(data) == ["sp", "patch"]
    assert list(data["sp"]) == list(data["patch"]) == ["hasty"]
    (sp,), (patch,) = data["sp"]["hasty"], data["patch"]["hasty"]
    assert sp["seed"] == patch["seed"] == plan(1, "hasty", 3)[0][3]
    # the table the CLI prints without --json, from these results
    results = {name: {"hasty": [TrialResult(**r) for r in data[name]["hasty"]]} for name in data}
    title, header, _, _, row, _, total = format_comparison(results, title_asked).splitlines()
    assert title == title_asked
    assert header.split() == ["participant", "sp", "|", "patch"]
    assert row.startswith("hasty")
    assert total.split("|")[0].split()[-2] == f"{int(sp['success'])}/1"
