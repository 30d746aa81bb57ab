"""app/cli/urdf.py: `hri-lab urdf check` prints check_urdf's tree and the joints, and a broken file
is one error naming the file and the line."""

import argparse
from pathlib import Path

import pytest

from app.cli import urdf
from app.cli.client import CliError

PAN_TILT = Path(__file__).resolve().parents[3] / "examples" / "urdf" / "pan_tilt.urdf"


def test_check_prints_the_tree_then_the_joints(capsys):
    assert urdf.check(argparse.Namespace(file=str(PAN_TILT), tree_only=False)) == 0
    out = capsys.readouterr().out
    assert out.startswith("robot name is: pan_tilt\n---------- Successfully Parsed XML ---------------\n")
    assert "root Link: base_link has 1 child(ren)" in out
    assert "        child(1):  tilt_link" in out
    assert "pan_joint (revolute): base_link -> pan_link  [-3.14, 3.14] rad  line 28" in out


def test_tree_only_leaves_the_joints_out(capsys):
    urdf.check(argparse.Namespace(file=str(PAN_TILT), tree_only=True))
    assert "Joints" not in capsys.readouterr().out


def test_a_broken_file_is_one_located_error(tmp_path):
    broken = tmp_path / "arm.urdf"
    broken.write_text(PAN_TILT.read_text().replace('<parent link="base_link"/>', '<parent link="nowhere"/>', 1))
    with pytest.raises(CliError) as error:
        urdf.check(argparse.Namespace(file=str(broken), tree_only=False))
    assert str(error.value).startswith(f"{broken}:")
    assert "nowhere" in str(error.value)
