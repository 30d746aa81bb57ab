"""The lab's `hri_lab` .srv/.action files (app/lab/interface_files.py) are its declarations' texts:
this fails when a declaration changed and `python -m app.lab.interface_files` was not run."""

import subprocess
import sys

from app.lab import interface_files


def test_the_shipped_files_are_the_declarations_texts():
    wanted, shipped = interface_files.lab_definitions(), interface_files.on_disk()
    assert wanted, "the lab declares hri_lab services and actions"
    stale = sorted(str(p.name) for p in set(shipped) - set(wanted))
    missing = sorted(str(p.name) for p in set(wanted) - set(shipped))
    differ = sorted(str(p.name) for p in set(wanted) & set(shipped) if wanted[p] != shipped[p])
    assert (stale, missing, differ) == ([], [], []), "run: python -m app.lab.interface_files"


def test_a_program_importing_hri_lab_imports_no_simulation(tmp_path):
    """What `from hri_lab.srv import DivideInts` costs a program: a file read, no numba, pinocchio, sim."""
    code = (
        "import sys\n"
        "from rosclient import interfaces\n"
        "interfaces.install([])\n"
        "from hri_lab.srv import DivideInts, DivideIntsRequest\n"
        "from hri_lab.action import Count\n"
        "assert DivideIntsRequest is DivideInts.Request and Count.Goal\n"
        "print(sorted(m for m in sys.modules if m.split('.')[0] in ('numba', 'pinocchio', 'sim', 'numpy')))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=True)
    assert out.stdout.strip() == "[]", out.stdout
