"""The lint configuration matches the code (pyproject.toml's [tool.ruff.lint]). Every C901 exemption
states the functions of its file above max-complexity, each with its complexity when it was
exempted: they are to be cut, not to grow. ruff itself (mccabe's count) measures them with the
exemptions left out: a stated function that grew fails, and so does one back under the bound or gone
(its exemption is stale: take it out), or one above the bound that no exemption states. The reading
is tried on a made-up file, so that it cannot pass by measuring nothing. And ruff reads every test."""

from __future__ import annotations

import json
import re
import subprocess
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RUFF = Path(sys.executable).with_name("ruff")  # pyproject's pinned ruff, in the venv the tests run in
EXEMPTION = re.compile(r'^"(?P<path>[^"]+)" = \[(?P<rules>[^\]]*)\]\s*#\s*C901:\s*(?P<why>.*)$')
STATED = re.compile(r"(\w+) \((\d+)\)")  # `record (24)`: a function and its complexity then
MEASURED = re.compile(r"`(\w+)` is too complex \((\d+) > \d+\)")


def stated(pyproject_text: str) -> dict[str, dict[str, int]]:
    """File -> {function: complexity} as the per-file-ignores' C901 comments state them."""
    found: dict[str, dict[str, int]] = {}
    for line in pyproject_text.splitlines():
        if (m := EXEMPTION.match(line)) and '"C901"' in m.group("rules"):
            found[m.group("path")] = {name: int(n) for name, n in STATED.findall(m.group("why"))}
    return found


def measured(root: Path, max_complexity: int) -> dict[str, dict[str, int]]:
    """File -> {function: complexity} of every function above max_complexity, the exemptions left out."""
    result = subprocess.run(
        [str(RUFF), "check", "--select", "C901", "--output-format", "json", "--exit-zero", "--no-cache"]
        + ["--config", "lint.per-file-ignores = {}", "--config", f"lint.mccabe.max-complexity = {max_complexity}", "."],
        cwd=root,
        capture_output=True,
        text=True,
        check=True,
    )
    found: dict[str, dict[str, int]] = {}
    for diagnostic in json.loads(result.stdout):
        m = MEASURED.search(diagnostic["message"])
        assert m, diagnostic["message"]
        path = Path(diagnostic["filename"]).resolve().relative_to(root.resolve()).as_posix()
        found.setdefault(path, {})[m.group(1)] = int(m.group(2))
    return found


def drift(bounds: dict[str, dict[str, int]], found: dict[str, dict[str, int]]) -> list[str]:
    """What the exemptions say that the code does not: each a line naming the file and function."""
    out = []
    for path in sorted(set(bounds) | set(found)):
        said, now = bounds.get(path, {}), found.get(path, {})
        for name in sorted(set(said) | set(now)):
            if name not in said:
                out.append(f"{path}: {name} ({now[name]}) is above the bound with no exemption stating it")
            elif name not in now:
                out.append(f"{path}: {name} is under the bound or gone: its exemption is stale")
            elif now[name] > said[name]:
                out.append(f"{path}: {name} grew from {said[name]} to {now[name]}")
    return out


def max_complexity() -> int:
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    return config["tool"]["ruff"]["lint"]["mccabe"]["max-complexity"]


def test_every_c901_exemption_is_true_and_none_grew():
    bounds = stated((ROOT / "pyproject.toml").read_text())
    assert bounds, "no C901 exemption read: the reading is broken"
    assert all(bounds.values()), "an exemption states no function with its complexity"
    assert drift(bounds, measured(ROOT, max_complexity())) == []


def test_the_reading_finds_growth_staleness_and_a_function_with_no_exemption(tmp_path):
    branches = "\n".join(f"    if x == {i}:\n        return {i}" for i in range(17))  # complexity 18
    (tmp_path / "grown.py").write_text(f"def grown(x):\n{branches}\n    return -1\n")
    (tmp_path / "cut.py").write_text("def cut(x):\n    return x\n")
    (tmp_path / "new.py").write_text(f"def new(x):\n{branches}\n    return -1\n")
    config = (
        '"grown.py" = ["C901"]  # C901: grown (16), to be cut\n'
        '"cut.py" = ["C901"]  # C901: cut (17), since cut\n'
        '"other.py" = ["F841"]  # not an exemption of C901\n'
    )
    bounds = stated(config)
    assert bounds == {"grown.py": {"grown": 16}, "cut.py": {"cut": 17}}
    found = measured(tmp_path, 15)
    assert found == {"grown.py": {"grown": 18}, "new.py": {"new": 18}}
    assert drift(bounds, found) == [
        "cut.py: cut is under the bound or gone: its exemption is stale",
        "grown.py: grown grew from 16 to 18",
        "new.py: new (18) is above the bound with no exemption stating it",
    ]


def test_ruff_reads_every_test_and_leaves_out_only_the_client_libraries_and_mkdocs_output():
    """`ruff check` covers every Python file under tests/ (tests/rosclient/site included: an
    exclusion of "site" once skipped it along with mkdocs' output) and none of rosclient/site's
    libraries, written as upstream's (ruff's `--show-files`: the files it would check)."""
    listed = subprocess.run([str(RUFF), "check", "--show-files"], cwd=ROOT, capture_output=True, text=True, check=True)
    checked = {Path(line).resolve() for line in listed.stdout.splitlines() if line.endswith(".py")}
    tests = {p.resolve() for p in (ROOT / "tests").rglob("*.py") if "__pycache__" not in p.parts}
    assert tests - checked == set()
    assert any(p.is_relative_to(ROOT / "tests" / "rosclient" / "site") for p in checked)
    assert not any(p.is_relative_to(ROOT / "rosclient" / "site") for p in checked)
