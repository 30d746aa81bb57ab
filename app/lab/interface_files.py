"""The lab's own interface package, `hri_lab`, as files: the .srv and .action texts of the lab's
declarations (app/lab/services.py, app/lab/actions.py) written under interfaces/share/hri_lab,
so that a program's `from hri_lab.srv import DivideInts` reads a file and imports no simulation.
`python -m app.lab.interface_files` writes them anew after a declaration changes; a test fails
while they differ (tests/app/lab/test_interface_files.py).
"""

from __future__ import annotations

from pathlib import Path

from interfaces.packages import SHARE

LAB_PACKAGE = "hri_lab"
GENERATED_KINDS = ("srv", "action")  # hri_lab/msg holds the topics' messages, written by hand


def lab_definitions() -> dict[Path, str]:
    """Each generated file's path (under interfaces/share) -> its text, from the declarations."""
    from app.lab.actions import ACTIONS
    from app.lab.services import SERVICES

    folder = SHARE / LAB_PACKAGE
    files = {
        folder / "srv" / f"{s.type.split('/')[-1]}.srv": s.srv for s in SERVICES if s.type.startswith(LAB_PACKAGE + "/")
    }
    files.update(
        (folder / "action" / f"{a.type.split('/')[-1]}.action", a.definition)
        for a in ACTIONS
        if a.type.startswith(LAB_PACKAGE + "/")
    )
    return {path: text if text.endswith("\n") else text + "\n" for path, text in files.items()}


def on_disk() -> dict[Path, str]:
    """The generated kinds' files as they are now."""
    folder = SHARE / LAB_PACKAGE
    return {
        p: p.read_text(encoding="utf-8") for kind in GENERATED_KINDS for p in sorted((folder / kind).glob(f"*.{kind}"))
    }


def write() -> list[Path]:
    """Write the files anew (and remove any whose declaration went); the paths written."""
    wanted = lab_definitions()
    for stale in set(on_disk()) - set(wanted):
        stale.unlink()
    for path, text in wanted.items():
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    return sorted(wanted)


if __name__ == "__main__":
    for written in write():
        print(written.relative_to(SHARE.parent.parent.parent))
