"""`hri-lab handout -o hri-lab-students.zip`: the lab as students get it (docs/instructors.md,
"What students get"): what runs the lab and what they read — the lab's packages (LAB), the page,
the examples, the docs site, the Makefile and pyproject.toml (`make run` works in it) — and none of
what grades them: no tests/ (the reference plug-in, the templates filled in, the filled nodes and
programs), no bench/. The autograder bundle carries the same lab (`lab_files`, one list). Its
README.md is the project's without the part about a checkout (`make test`, tests/README.md): the
README's `checkout` section (`handout_readme`)."""

from __future__ import annotations

import argparse
import re
import sys
import zipfile
from pathlib import Path

import sim

TOP = Path(sim.__file__).resolve().parent.parent  # the checkout: the packages' folder
LAB = (
    "sim",
    "interfaces",
    "app",
    "rosclient",
    "static",
)  # what the lab runs on (static/: the page the server mounts)
LAB_FILES = ("pyproject.toml", "README.md")
COURSE = ("examples", "docs")  # what a student reads and runs beside the lab
COURSE_FILES = ("Makefile", "mkdocs.yml", "CHANGELOG.md")
NEVER = ("tests", "bench", ".ci")  # what grades the students, or measures the lab
CHECKOUT = re.compile(r"<!-- --8<-- \[start:checkout\] -->\n.*?<!-- --8<-- \[end:checkout\] -->\n", re.S)


def lab_files(course: bool = False) -> list[tuple[Path, str]]:
    """(file, name in the zip): the lab's source (pyproject.toml first), and with `course` what a
    student's install holds beside it."""
    files = [(TOP / name, name) for name in LAB_FILES + (COURSE_FILES if course else ())]
    for folder in LAB + (COURSE if course else ()):
        for path in sorted((TOP / folder).rglob("*")):
            if path.is_file() and "__pycache__" not in path.parts and path.suffix not in (".nbi", ".nbc", ".pyc"):
                files.append((path, path.relative_to(TOP).as_posix()))
    assert not any(name.split("/")[0] in NEVER for _, name in files)
    return files


def handout_readme() -> str:
    """The project's README without its `checkout` section (the tests, the linters: what the
    handout does not hold)."""
    text = (TOP / "README.md").read_text(encoding="utf-8")
    kept = CHECKOUT.sub("", text)
    if kept == text:
        raise RuntimeError("README.md has no checkout section (<!-- --8<-- [start:checkout] -->)")
    return kept


def run(args: argparse.Namespace) -> int:
    files = lab_files(course=True)
    if not files[0][0].is_file():
        print("hri-lab handout: the lab's source (pyproject.toml) is not beside its packages", file=sys.stderr)
        return 2
    with zipfile.ZipFile(args.output, "w", zipfile.ZIP_DEFLATED) as bundle:
        for path, name in files:
            if name == "README.md":
                bundle.writestr(f"{args.folder}/{name}", handout_readme())
            else:
                bundle.write(path, f"{args.folder}/{name}")
    print(f"{args.output}: the lab for students in {args.folder}/ ({len(files)} files; no tests/, no bench/)")
    return 0
