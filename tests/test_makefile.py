"""The Makefile's choice of the interpreter the venv is made from: the system's python3 when it is
3.11 or newer (a distribution's build, optimized), else python3 on PATH; a venv made from another
interpreter is made again. Read from `make -n` (what it would run), against a venv folder of the test's."""

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BASE = Path(sys._base_executable)  # the interpreter this venv was made from: 3.11 or newer


def would_run(venv: Path, *variables: str) -> str:
    done = subprocess.run(
        ["make", "-n", f"VENV={venv}", *variables, f"{venv}/.installed"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode == 0, done.stderr
    return done.stdout


def made_venv(folder: Path, home: Path) -> Path:
    """A venv folder as `python -m venv` leaves it, made from `home`, installed after pyproject.toml."""
    venv = folder / ".venv"
    (venv / "bin").mkdir(parents=True)
    (venv / "bin" / "python").symlink_to(sys.executable)
    (venv / "pyvenv.cfg").write_text(f"home = {home}\ninclude-system-site-packages = false\n")
    (venv / ".installed").touch()
    later = (ROOT / "pyproject.toml").stat().st_mtime + 10
    os.utime(venv / ".installed", (later, later))
    return venv


def test_the_system_python_when_it_is_new_enough(tmp_path):
    lines = would_run(tmp_path / ".venv", f"SYSTEM_PYTHON={BASE}")
    assert f"{BASE} -m venv --clear {tmp_path}/.venv" in lines


def test_python3_on_path_when_the_system_python_is_too_old(tmp_path):
    old = tmp_path / "python3.10"  # answers as a Python 3.10 would to the Makefile's question
    old.write_text("#!/bin/sh\nexit 1\n")
    old.chmod(0o755)
    lines = would_run(tmp_path / ".venv", f"SYSTEM_PYTHON={old}")
    assert f"python3 -m venv --clear {tmp_path}/.venv" in lines
    assert str(old) not in lines


def test_a_venv_made_from_the_chosen_python_is_kept_and_one_made_from_another_is_made_again(tmp_path):
    kept = made_venv(tmp_path / "kept", BASE.parent)
    assert "is up to date" in would_run(kept, f"PYTHON={BASE}")
    other = made_venv(tmp_path / "other", Path("/opt/another/bin"))
    assert f"{BASE} -m venv --clear {other}" in would_run(other, f"PYTHON={BASE}")
