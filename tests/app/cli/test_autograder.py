"""app/cli/autograder.py in this process: the bundle's files and config, the public seed refused
(what runs in the container: tests/app/grading/test_gradescope.py; the bundle run as Gradescope runs it:
tests/e2e/test_gradescope.py; its CLI: tests/e2e/test_autograder.py)."""

import json
import zipfile

from app.cli.autograder import CONFIG, SOURCE, build
from app.cli.main import build_parser
from app.grading.report import PUBLIC_SEED


def bundle_args(tmp_path, *argv: str):
    return build_parser().parse_args(["autograder", "-o", str(tmp_path / "autograder.zip"), *argv])


def test_the_bundle_holds_the_scripts_executable_the_config_and_the_labs_source(tmp_path, capsys):
    assert build(bundle_args(tmp_path, "--seed", "31", "--services", "--hide-until-due")) == 0
    with zipfile.ZipFile(tmp_path / "autograder.zip") as z:
        names = set(z.namelist())
        for script in ("setup.sh", "run_autograder"):
            assert z.getinfo(script).external_attr >> 16 == 0o100755
        config = json.loads(z.read(CONFIG))
        setup = z.read("setup.sh").decode()
    assert {
        f"{SOURCE}/pyproject.toml",
        f"{SOURCE}/sim/world.py",
        f"{SOURCE}/app/cli/autograder.py",
        f"{SOURCE}/app/grading/gradescope.py",
    } <= names
    assert config["seed"] == 31
    assert config["services"]
    assert config["hide_until_due"]
    assert config["reference"] == "zero"
    assert f'"$ROOT/source/{SOURCE}[nodes]"' in setup  # --services: roslibpy installed for the nodes
    assert "seed 31" in capsys.readouterr().out


def test_the_public_seed_is_refused_unless_asked_for(tmp_path, capsys, monkeypatch):
    """Seed 0 is what every student grades with at home: a bundle with it would grade with numbers
    the students know. Refused (exit 2, saying why) unless --public-seed; $HRI_LAB_GRADE_SEED is
    the course's seed when --seed is not given."""
    monkeypatch.delenv("HRI_LAB_GRADE_SEED", raising=False)
    assert build(bundle_args(tmp_path)) == 2
    err = capsys.readouterr().err
    assert f"seed {PUBLIC_SEED} is the public default" in err
    assert "--public-seed" in err
    assert not (tmp_path / "autograder.zip").exists()
    assert build(bundle_args(tmp_path, "--public-seed")) == 0
    assert f"seed {PUBLIC_SEED}, the public default" in capsys.readouterr().out
    with zipfile.ZipFile(tmp_path / "autograder.zip") as z:
        assert "[nodes]" not in z.read("setup.sh").decode()  # no --services: no roslibpy
    monkeypatch.setenv("HRI_LAB_GRADE_SEED", "77")
    assert build(bundle_args(tmp_path)) == 0
    assert "seed 77, a private seed" in capsys.readouterr().out
