"""app/cli/outputs.py: --record DIR and --plots DIR make their folders (or stop with the reason);
without either there is nothing to write."""

import argparse

import pytest

from sim.recording.trial import TrialOutputs

from app.cli.outputs import trial_outputs


def test_no_folder_no_outputs():
    assert trial_outputs(argparse.Namespace(record=None, plots=None)) is None
    assert trial_outputs(argparse.Namespace()) is None


def test_the_folders_are_made(tmp_path):
    record, plots = tmp_path / "a" / "rec", tmp_path / "b" / "fig"
    outputs = trial_outputs(argparse.Namespace(record=str(record), plots=str(plots)))
    assert isinstance(outputs, TrialOutputs)
    assert record.is_dir()
    assert plots.is_dir()


def test_a_folder_that_cannot_be_made_stops_with_its_reason(tmp_path):
    (tmp_path / "file").write_text("")
    with pytest.raises(SystemExit, match=r"cannot write to .*file/rec"):
        trial_outputs(argparse.Namespace(record=str(tmp_path / "file" / "rec"), plots=None))
