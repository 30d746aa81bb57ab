"""scripts/system-deps.sh, as a normal user would run it (`make run`/`make test` call it): with the
packages present it says nothing and goes on; with one missing it prints the exact `sudo apt-get
install` line and stops (never apt-get itself); for `make run`, a missing bubblewrap is said and the
lab starts anyway. Run as the unprivileged user nobody, with a PATH that lacks the missing program."""

import os
import shutil
import subprocess
import tempfile
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parent.parent / "scripts" / "system-deps.sh"
NOBODY = 65534


@pytest.fixture
def bin_dir():
    """A PATH with the tools the script uses, bubblewrap and wrk left out (in a folder that nobody
    can read: pytest's tmp_path is root's alone)."""
    top = Path(tempfile.mkdtemp(prefix="hri-lab-deps-"))
    os.chmod(top, 0o755)
    folder = top / "bin"
    folder.mkdir()
    for tool in ("sh", "id", "grep", "python3", "make", "apt-get"):
        found = shutil.which(tool, path="/usr/bin:/bin")  # the system's (a venv's python may be unreadable to nobody)
        assert found, f"{tool} is needed on this machine"
        (folder / tool).symlink_to(found)
    yield folder
    shutil.rmtree(top)


def run_as_nobody(path: str, *groups: str) -> subprocess.CompletedProcess:
    """The script as uid/gid nobody (setpriv), with only PATH in its environment."""
    if os.geteuid() == 0:
        command = [
            shutil.which("setpriv") or "setpriv",
            f"--reuid={NOBODY}",
            f"--regid={NOBODY}",
            "--clear-groups",
            "sh",
            str(SCRIPT),
            *groups,
        ]
    else:
        command = ["sh", str(SCRIPT), *groups]
    return subprocess.run(command, env={"PATH": path}, capture_output=True, text=True, timeout=60)


def test_all_present_is_silent(bin_dir):
    done = run_as_nobody(str(bin_dir), "python", "make", "egl")
    assert (done.returncode, done.stdout, done.stderr) == (0, "", "")


def test_a_missing_package_prints_the_sudo_line_and_stops(bin_dir):
    done = run_as_nobody(str(bin_dir), "egl", "bubblewrap", "wrk")
    assert done.returncode == 1
    assert "    sudo apt-get install -y bubblewrap wrk\n" in done.stderr
    assert "Permission denied" not in done.stderr and "lock" not in done.stderr  # apt-get never ran


def test_a_missing_optional_sandbox_is_said_and_the_run_goes_on(bin_dir):
    done = run_as_nobody(str(bin_dir), "egl", "--optional", "bubblewrap")
    assert done.returncode == 0
    assert "WITHOUT the sandbox" in done.stderr and "sudo apt-get install -y bubblewrap" in done.stderr


def test_without_apt_it_names_the_packages_and_the_image(bin_dir):
    (bin_dir / "apt-get").unlink()
    done = run_as_nobody(str(bin_dir), "bubblewrap")
    assert done.returncode == 1
    assert "no apt-get" in done.stderr and "(bubblewrap)" in done.stderr and "container image" in done.stderr


def test_an_unknown_group_is_refused(bin_dir):
    done = run_as_nobody(str(bin_dir), "nothing-such")
    assert done.returncode == 2 and "unknown group 'nothing-such'" in done.stderr
