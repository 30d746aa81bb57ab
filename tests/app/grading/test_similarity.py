"""The batch's similarity report (app/grading/similarity.py): a copy of the lab's SP and two files that
differ only in their names are flagged; a file written from the template is not."""

import csv
from pathlib import Path

from app.cli.templates import render
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


def test_honest_fills_of_the_template_are_not_flagged_and_a_copied_fill_is(tmp_path):
    """The template's own text is copydetect's boilerplate: files built on it share it by design,
    so only what a student wrote counts (two honest fills, two unfilled templates: no flag), and a
    fill copied with its names changed is flagged."""
    batch = tmp_path / "batch"
    batch.mkdir()
    own_style = (CONTROLLERS / "template_filled_own_style.py").read_text()
    (batch / "alice.py").write_text((CONTROLLERS / "template_filled.py").read_text())
    (batch / "erin.py").write_text(own_style)
    (batch / "frank.py").write_text(render("controller"))  # handed in as given
    (batch / "gina.py").write_text(render("controller"))
    copied = own_style.replace("push", "f_normal").replace("shear", "f_tangent").replace("capped", "clip_norm")
    (batch / "hugo.py").write_text(copied)
    pairs = compare(sorted(batch.glob("*.py")), tmp_path / "reports", threshold=0.5)
    flagged = {frozenset(Path(name).name for name in (p.file, p.other)) for p in pairs if p.flagged}
    assert flagged == {frozenset(("erin.py", "hugo.py"))}, [p for p in pairs if p.flagged]
    honest = {
        frozenset(("alice.py", "erin.py")),
        frozenset(("frank.py", "gina.py")),
        frozenset(("alice.py", "gina.py")),
    }
    for pair in pairs:
        if frozenset((Path(pair.file).name, Path(pair.other).name)) in honest:
            assert max(pair.share_of_file, pair.share_of_other) < 0.25, pair  # half the threshold
