"""One source per fact, enforced on the whole tree:

- the SP steps are numbered once, in docs/method.md ("0. **Low-pass**: ..."); every "step N" in the
  code, the templates, the tests and the pages is one of those labels (the patch controller's own
  steps are "patch step N", numbered in sim/controllers/patch.py), and a label written with a
  step's name ("step 6's rate limit", "(0: low-pass ...") names that step;
- the defaults the pages quote are placeholders the docs hook fills from the code
  (`{{ LiftingParams.k_n }}`, docs/hooks/reference.py): a hand copy of a default fails, and so does a
  placeholder that names no field;
- the band's width is `LiftingParams.f_n_band`: "force + 5" is not written again.

Each rule is tested on made-up text too, so that it cannot pass by seeing nothing."""

from __future__ import annotations

import dataclasses
import importlib.util
import re
from pathlib import Path

import pytest

from sim.controllers.interface import LiftingParams
from sim.monitor import TrialRules

ROOT = Path(__file__).resolve().parent.parent
METHOD = ROOT / "docs" / "method.md"
PATCH = ROOT / "sim" / "controllers" / "patch.py"
HISTORY = ("CHANGELOG.md", "docs/changelog.md")  # what was true then, in the words of then
SCANNED = (
    "sim",
    "interfaces",
    "app",
    "rosclient",
    "docs",
    "tests",
    "bench",
    "examples",
    "static",
    "README.md",
)

LABELS = r"[0-9][ab]?(?:(?:-|, and |, | and )[0-9][ab]?)*(?![0-9])"
STEP = re.compile(rf"(?<![-\w])(patch |SP's |SP )?[Ss]teps? ({LABELS})", re.IGNORECASE)


def sp_steps(text: str) -> dict[str, str]:
    """method.md's numbered SP steps: label -> name ("0" -> "low-pass", "5a" -> "saturation")."""
    steps = {}
    number = ""
    for line in text.splitlines():
        if item := re.match(r"([0-9])\. (a\. )?\*\*(.+?)\*\*", line):
            number = item.group(1)
            steps[number + ("a" if item.group(2) else "")] = item.group(3).lower()
        elif (sub := re.match(r" +b\. \*\*(.+?)\*\*", line)) and number:
            steps[number + "b"] = sub.group(1).lower()
    return steps


def patch_steps(text: str) -> set[str]:
    """The patch controller's own steps, the numbered list of its module docstring."""
    docstring = text.split('"""')[1]
    return {m.group(1) for m in re.finditer(r"^([0-9])\. ", docstring, re.MULTILINE)}


def label_problems(text: str, sp: dict[str, str], patch: set[str]) -> list[str]:
    """Every step label in `text` that is not a step, or that carries another step's name."""
    problems = []
    for match in STEP.finditer(text):
        known = patch if (match.group(1) or "").lower() == "patch " else set(sp)
        for label in re.split(r"-|, and |, | and ", match.group(2)):
            if label not in known:
                problems.append(f"{match.group(0)!r}: no {'patch ' if known is patch else ''}step {label}")
    names = "|".join(re.escape(name) for name in sp.values())
    for match in re.finditer(rf"(?<![\w.])([0-9][ab]?)(?:'s|:)? \(?((?i:{names}))", text):
        named = next(label for label, name in sp.items() if name == match.group(2).lower())
        if match.group(1) != named:
            problems.append(f"{match.group(0)!r}: {match.group(2)} is step {named}")
    return problems


def tree_files(suffixes: tuple[str, ...]) -> list[Path]:
    files = []
    for top in SCANNED:
        path = ROOT / top
        files += [path] if path.is_file() else sorted(p for p in path.rglob("*") if p.suffix in suffixes)
    skip = (*HISTORY, "tests/test_one_source.py")  # the history, and this file's made-up drifts
    return [f for f in files if f.relative_to(ROOT).as_posix() not in skip and "__pycache__" not in f.parts]


def test_method_md_numbers_the_sp_steps_once():
    steps = sp_steps(METHOD.read_text())
    assert list(steps) == ["0", "1", "2", "3", "4", "5a", "5b", "6"], steps
    assert steps["6"] == "rate limit"
    assert steps["0"] == "low-pass"
    assert patch_steps(PATCH.read_text()) == {str(n) for n in range(1, 9)}


def test_every_step_label_in_the_tree_is_method_md_s():
    sp, patch = sp_steps(METHOD.read_text()), patch_steps(PATCH.read_text())
    problems = {
        f.relative_to(ROOT).as_posix(): found
        for f in tree_files((".py", ".md", ".js", ".html"))
        if (found := label_problems(f.read_text(), sp, patch))
    }
    assert problems == {}


def test_the_label_check_finds_a_drifted_step():
    sp, patch = sp_steps(METHOD.read_text()), patch_steps(PATCH.read_text())
    assert label_problems("steps 0, 2, 5b and 6; steps 1-5a; step 6's rate limit; patch step 8", sp, patch) == []
    assert label_problems("# TODO step 5: saturate, rotate, then limit the rate", sp, patch) == ["'step 5': no step 5"]
    assert label_problems("TODOs at each SP step (0: low-pass F_ext ... 5: rate limit)", sp, patch) == [
        "'5: rate limit': rate limit is step 6"
    ]
    assert label_problems("step 4's rate limit, patch step 9, --steps 5000, step 47 us", sp, patch) == [
        "'patch step 9': no patch step 9",
        '"4\'s rate limit": rate limit is step 6',
    ]


# --- the defaults the pages quote ---------------------------------------------------------------

DEFAULTS = {"LiftingParams": LiftingParams(), "TrialRules": TrialRules()}
SET_BY_SERVICES = ("f_n_min",)  # start/stop set it: `f_n_min = 0` is what stop() does, not a default


def hook():
    spec = importlib.util.spec_from_file_location("docs_hook", ROOT / "docs" / "hooks" / "reference.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def hand_copies(text: str) -> list[str]:
    """A default written out by hand next to its field's name: `k_n` [0.005 ...], alpha = 0.5, ...
    (in the prose: a fenced block is a program's output or input, as it was printed)."""
    prose = re.sub(r"^```.*?^```", "", text, flags=re.MULTILINE | re.DOTALL)
    found = []
    for name, instance in DEFAULTS.items():
        for field in dataclasses.fields(instance):
            default = getattr(instance, field.name)
            if field.name in SET_BY_SERVICES or isinstance(default, bool) or not isinstance(default, (int, float)):
                continue
            number = re.escape(f"{default:g}")
            quoted = rf"`{field.name}` ?(?:\[|\(|=)\s*{number}(?![0-9])"  # `k_n` [0.005 ...], `mu` (0.5), `mu` = 0.5
            stated = (
                rf"\b{field.name} = {number}(?![0-9])"  # alpha = 0.5 (a command's alpha=0.5 is a choice, not a copy)
            )
            found += [f"{name}.{field.name}: {m.group(0)!r}" for m in re.finditer(f"{quoted}|{stated}", prose)]
    found += [f"a default in brackets: {m.group(0)!r}" for m in re.finditer(r"`\w+` \[[0-9][^\]]*\]", prose)]
    return found


def docs_pages() -> list[Path]:
    return [p for p in sorted((ROOT / "docs").rglob("*.md")) if p.relative_to(ROOT).as_posix() not in HISTORY]


def test_no_page_copies_a_default_by_hand():
    assert {p.name: found for p in docs_pages() if (found := hand_copies(p.read_text()))} == {}


def test_the_success_rule_s_numbers_are_placeholders():
    text = (ROOT / "docs" / "experiment.md").read_text()
    rule = text.split("## The success rule", 1)[1].split("\n## ", 1)[0]
    without = hook().VALUE.sub("", rule)
    assert re.findall(r"[0-9]", without) == [], "a number of the success rule written by hand"
    assert len(hook().VALUE.findall(rule)) >= 5


def test_every_placeholder_is_filled_from_the_code():
    docs_hook = hook()
    filled = {}
    for page in docs_pages():
        for match in docs_hook.VALUE.finditer(page.read_text()):
            filled[match.group(0)] = docs_hook.value(match)
    assert filled["{{ LiftingParams.f_n_band }}"] == f"{LiftingParams().f_n_band:g}"
    assert filled["{{ TrialRules.max_slip | cm }}"] == f"{TrialRules().max_slip * 100:g}"
    assert filled["{{ LiftingParams.alpha }}"] == f"{LiftingParams().alpha:g}"
    with pytest.raises(ValueError, match="unknown placeholder"):
        docs_hook.value(docs_hook.VALUE.search("{{ LiftingParams.no_such_gain }}"))


def test_the_copy_check_finds_a_hand_copy():
    assert hand_copies("`k_t` [{{ LiftingParams.k_t }} (m/s)/N], alpha {{ LiftingParams.alpha }}") == []
    assert hand_copies("`k_t` [0.1 (m/s)/N]") == [
        "LiftingParams.k_t: '`k_t` [0.1'",
        "a default in brackets: '`k_t` [0.1 (m/s)/N]'",
    ]
    assert hand_copies("the margin alpha = 0.5 here") == ["LiftingParams.alpha: 'alpha = 0.5'"]


# --- the band's width ---------------------------------------------------------------------------

BAND_COPY = re.compile(r"\b(?:force|f_n_min|f_n_min\"\]|f_n_min'\])\s*\+\s*5(?:\.0)?\b(?! *\*)")
# Where "+ 5" is still written this round, each with its reason: the students' starting files quote
# the handout (their facts are filled from LiftingParams by the templates' own change), the probe
# names are named in reports and in tests/e2e/test_grading.py (renamed after the merges), and the
# programs under tests/ are written as students write them.
BAND_QUOTES = (
    "app/cli/templates/",
    "tests/nodes/",
    "tests/ros_programs/",
    "tests/e2e/test_grading.py",
    "app/grading/probe_stream.py:start and stop set the band [force, force + 5] and running",
    "app/grading/probe_stream.py:the band's upper end is f_n_min + 5 N",
)


def band_copies(relative: str, text: str) -> list[str]:
    return [
        f"{relative}:{number}: {line.strip()}"
        for number, line in enumerate(text.splitlines(), 1)
        if BAND_COPY.search(line)
        and not any(relative.startswith(q.split(":")[0]) and q.partition(":")[2] in line for q in BAND_QUOTES)
    ]


def test_the_band_s_width_is_written_once():
    found = []
    for f in tree_files((".py", ".md")):
        found += band_copies(f.relative_to(ROOT).as_posix(), f.read_text())
    assert found == []


def test_the_band_check_finds_a_copy():
    assert band_copies("sim/x.py", "f_n_max = force + 5.0") == ["sim/x.py:1: f_n_max = force + 5.0"]
    assert band_copies("docs/x.md", "f_n_max = force + f_n_band") == []


# --- the README and the site's home page; the figures --------------------------------------------


def test_the_readme_and_the_home_page_share_one_intro():
    readme, index = (ROOT / "README.md").read_text(), (ROOT / "docs" / "index.md").read_text()
    intro = readme.split("[start:intro] -->", 1)[1].split("<!-- --8<-- [end:intro]", 1)[0]
    assert "hri-lab is a simulated" in intro
    assert '--8<-- "README.md:intro"' in index
    assert '--8<-- "README.md:paper"' in index
    copied = [line for line in readme.splitlines() if len(line) > 40 and line in index]
    assert copied == []


def test_the_readme_links_to_the_figures_instead_of_copying_them():
    readme = (ROOT / "README.md").read_text()
    measured = readme.split("## Measured", 1)[1].split("\n## ", 1)[0]
    assert "(docs/performance.md)" in measured
    assert re.findall(r"[0-9]", measured) == []
