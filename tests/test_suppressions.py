"""Every `# noqa` names the rules it silences and says why ("# noqa: BLE001 - a listener that is
gone does not stop the others"): a suppression nobody can read the reason of is never removed.
Those written before the rule, in files others are changing this round, are listed with what they
silence, to be given their reason after the merges; a listed one that is gone fails too."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
NOQA = re.compile(r"#\s*noqa\b(?P<rest>.*)$")
REASONED = re.compile(r":\s*[A-Z]+[0-9]+(?:\s*,\s*[A-Z]+[0-9]+)*\s*(?:-|—|:|\()\s*\S")
NOT_YET = {}


def unreasoned(text: str) -> list[str]:
    return [
        line.strip() for line in text.splitlines() if (m := NOQA.search(line)) and not REASONED.match(m.group("rest"))
    ]


def test_every_noqa_says_why():
    found = {}
    for top in ("sim", "interfaces", "app", "rosclient", "tests", "bench", "examples", "docs"):
        for path in sorted((ROOT / top).rglob("*.py")):
            if lines := unreasoned(path.read_text()):
                found[path.relative_to(ROOT).as_posix()] = len(lines)
    found.pop("tests/test_suppressions.py", None)  # the made-up lines below
    assert found == NOT_YET


def test_the_check_reads_a_reason():
    assert unreasoned("x = 1  # noqa: E731 - a one-line helper") == []
    assert unreasoned("import a  # noqa: F401, E402 - imported for its side effect") == []
    assert unreasoned("except Exception:  # noqa: BLE001") == ["except Exception:  # noqa: BLE001"]
    assert unreasoned("import a  # noqa") == ["import a  # noqa"]
