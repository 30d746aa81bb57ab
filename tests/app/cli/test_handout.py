"""The lab as students get it (app/cli/handout.py): what runs the lab and what they read, none of
what grades them (the reference plug-in, the templates filled in, the filled nodes and programs)."""

import argparse
import re
import zipfile

from app.cli.handout import lab_files, run

SOLUTIONS = ("reference_sp.py", "template_filled.py", "services_solution.py", "lifting_solution.py")


def test_the_students_zip_holds_the_lab_and_no_solution(tmp_path, capsys):
    out = tmp_path / "students.zip"
    assert run(argparse.Namespace(output=str(out), folder="hri-lab")) == 0
    with zipfile.ZipFile(out) as z:
        names = [n.removeprefix("hri-lab/") for n in z.namelist()]
    assert {"Makefile", "pyproject.toml", "static/index.html", "app/cli/templates/services_rospy.py"} <= set(names)
    assert "sim/controllers/template.py" in names
    assert "docs/students.md" in names
    assert "examples/04_grade_a_file.py" in names
    assert not [n for n in names if n.split("/")[0] in ("tests", "bench", ".ci")]
    assert not [n for n in names if n.rsplit("/", 1)[-1] in SOLUTIONS]
    assert "no tests/" in capsys.readouterr().out


def test_the_autograder_bundle_carries_the_lab_alone():
    names = {name for _, name in lab_files()}
    assert {"pyproject.toml", "static/index.html"} <= names
    assert any(n.startswith("interfaces/") and n.endswith("/String.msg") for n in names)  # the message texts
    assert "rosclient/boot.py" in names  # the client `hri-lab run` starts a program in
    assert not [n for n in names if n.split("/")[0] in ("docs", "examples", "tests", "bench")]


def test_the_zips_readme_names_only_what_the_zip_holds(tmp_path):
    """Every link of the handout's README is a file in it, every `make TARGET` a target of its
    Makefile whose recipe needs nothing the handout leaves out (tests/, bench/)."""
    out = tmp_path / "students.zip"
    assert run(argparse.Namespace(output=str(out), folder="hri-lab")) == 0
    with zipfile.ZipFile(out) as z:
        z.extractall(tmp_path / "unpacked")
    top = tmp_path / "unpacked" / "hri-lab"
    readme = (top / "README.md").read_text(encoding="utf-8")
    assert "make run" in readme
    links = [
        link.split("#")[0]
        for link in re.findall(r"\]\(([^)\s]+)\)", readme)
        if not re.match(r"[a-z]+:", link) and not link.startswith("#")
    ]
    assert "docs/students.md" in links
    assert [link for link in links if not (top / link).is_file()] == []
    makefile = (top / "Makefile").read_text(encoding="utf-8")
    recipes = dict(re.findall(r"^([\w-]+):[^=\n]*\n((?:\t.*\n)*)", makefile, re.M))
    targets = set(re.findall(r"\bmake ([\w-]+)", readme))
    assert {"run", "docs"} <= targets
    assert [t for t in targets if t not in recipes] == []
    absent = [t for t in targets if re.search(r"\b(tests|bench)\b|pytest", recipes[t])]
    assert absent == [], "the README names targets that need what the handout leaves out"
    assert "tests/" not in readme
