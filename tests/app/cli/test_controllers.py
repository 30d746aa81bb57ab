"""app/cli/controllers.py: --controller sp|patch|FILE.py[:Class] as a factory; a file that cannot
load stops the command at once with its reason and exit code 2 (loaded unsandboxed here: a unit
test starts no other program; the sandboxed load is tests/e2e's)."""

from pathlib import Path

import pytest

from sim.controllers.patch import PatchController
from sim.controllers.sp import SPController

from app.cli.controllers import loaded_factory

CONTROLLERS = Path(__file__).resolve().parents[2] / "controllers"


def test_built_in_names_give_their_controllers():
    assert type(loaded_factory("sp", sandboxed=False)()) is SPController
    assert type(loaded_factory("patch", sandboxed=False)()) is PatchController


def test_a_file_s_class_is_loaded():
    controller = loaded_factory(f"{CONTROLLERS / 'reference_sp.py'}", sandboxed=False)()
    assert callable(controller.step)
    assert callable(controller.reset)


@pytest.mark.parametrize("spec", ["missing.py", f"{CONTROLLERS / 'reference_sp.py'}:NoSuchClass", "pid"])
def test_what_cannot_load_exits_2_with_its_reason(spec, capsys):
    with pytest.raises(SystemExit) as stopped:
        loaded_factory(spec, sandboxed=False)
    assert stopped.value.code == 2
    assert capsys.readouterr().err.startswith("hri-lab: controller: ")
