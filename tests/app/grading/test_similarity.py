"""The batch's similarity report (app/grading/similarity.py): a copy of the lab's SP and two files that
differ only in their names are flagged; a file written from the template is not."""

import csv
from pathlib import Path

from app.grading.similarity import FIELDS, compare, reference_files

CONTROLLERS = Path(__file__).resolve().parents[2] / "controllers"


def test_copies_and_renamed_pairs_are_flagged_and_an_honest_file_is_not(tmp_path):
    batch = tmp_path / "batch"
    batch.mkdir()
    honest = (CONTROLLERS / "template_filled.py").read_text()
    sp = next(p for p in reference_files() if p.name == "sp.py")
    (batch / "alice.py").write_text(honest)
    (batch / "bob.py").write_text(honest.replace("wrench", "force").replace("params", "p"))  # names changed
    (batch / "carol.py").write_text(sp.read_text() + "\n\nclass CooperativeLifting(SPController):\n    pass\n")
    (batch / "dave.py").write_text((CONTROLLERS / "sleeper.py").read_text())
    out = tmp_path / "reports"
    pairs = compare(sorted(batch.glob("*.py")), out, threshold=0.5)
    flagged = {frozenset((Path(p.file).name, Path(p.other).name)) for p in pairs if p.flagged}
    assert {frozenset(("alice.py", "bob.py")), frozenset(("carol.py", "sp.py"))} <= flagged, pairs[:4]
    references = {p.name for p in reference_files()}
    others = flagged - {frozenset(("alice.py", "bob.py"))}
    assert all("carol.py" in pair and pair - {"carol.py"} <= references for pair in others), others  # only the copy
    assert compare(sorted(batch.glob("*.py")), tmp_path / "again", threshold=0.5) == pairs  # the same every run
    carol = next(p for p in pairs if Path(p.file).name == "carol.py" and p.other == str(sp))
    assert carol.other_is_reference
    assert carol.share_of_other == 1.0
    honest_vs_sp = next(p for p in pairs if Path(p.file).name == "alice.py" and p.other == str(sp))
    assert max(honest_vs_sp.share_of_file, honest_vs_sp.share_of_other) < 0.2
    with (out / "similarity.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert tuple(rows[0]) == FIELDS
    assert len(rows) == len(pairs) == 4 * 3 // 2 + 4 * len(reference_files())
    assert rows[0]["flagged"] == "True"
    html = (out / "similarity.html").read_text()
    assert "carol.py" in html
    assert "bob.py" in html
