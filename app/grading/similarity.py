"""The similarity report of a graded batch (`hri-lab grade ... --out DIR`): every pair of the
batch's files and each file against the lab's own controllers (the files of the modules the
sandbox watches, sim/controllers/sandbox/child.py's REFERENCE_MODULES), by copydetect's winnowing
(MOSS's method: fingerprints of every 25-token stretch, names and literals abstracted), written
beside the reports as `similarity.csv` (every pair) and `similarity.html` (copydetect's report of
the pairs at or above the threshold, their shared code highlighted). A pair is flagged when either
file has at least `threshold` of its tokens in the other. The controller template (`hri-lab
template`, sim/controllers/template.py) is copydetect's boilerplate: what every file built on it
shares by design is never counted, only what its author wrote.

copydetect fingerprints k-grams with Python's `hash()`, which every process salts differently: the
comparison runs in a child process with PYTHONHASHSEED=0, so a batch's report is the same wherever
and whenever it is made (a resumed batch, a Dask cluster's run and the local run agree)."""

from __future__ import annotations

import csv
import importlib.util
import io
import os
import subprocess
import sys
import warnings
from dataclasses import dataclass
from pathlib import Path

from sim.controllers.plugin import template_path
from sim.controllers.sandbox.child import REFERENCE_MODULES

NOISE_TOKENS = 25  # copydetect's k: a shared stretch shorter than this is never counted
GUARANTEE_TOKENS = 30  # a shared stretch this long is always found (winnowing's window: 30 - 25 + 1)
THRESHOLD = 0.5  # default: a pair is flagged when half of either file's tokens are in the other
FIELDS = ("file", "other", "share_of_file", "share_of_other", "other_is_reference", "flagged")


@dataclass(frozen=True)
class Pair:
    file: str
    other: str
    share_of_file: float  # of `file`'s tokens, the share found in `other`
    share_of_other: float
    other_is_reference: bool
    flagged: bool


def reference_files() -> list[Path]:
    """The source files of the lab's own controllers and kernels."""
    found = []
    for name in REFERENCE_MODULES:
        spec = importlib.util.find_spec(name)
        if spec is not None and spec.origin:
            found.append(Path(spec.origin))
    return found


def compare(files: list[Path], out: Path, threshold: float = THRESHOLD) -> list[Pair]:
    """Every pair of `files` and each against the lab's reference, written to out/similarity.csv and
    out/similarity.html; the pairs, flagged first, the most similar first (computed in a child
    process with a fixed hash seed: see the module's docstring)."""
    command = [sys.executable, "-m", "app.grading.similarity", str(out), repr(threshold), *map(str, files)]
    env = dict(os.environ, PYTHONHASHSEED="0")
    done = subprocess.run(command, env=env, capture_output=True, text=True, timeout=600)
    if done.returncode != 0:
        raise RuntimeError(done.stderr.strip().splitlines()[-1] if done.stderr.strip() else "the comparison failed")
    with (out / "similarity.csv").open(encoding="utf-8", newline="") as table:
        rows = list(csv.DictReader(table))
    return [
        Pair(
            r["file"],
            r["other"],
            float(r["share_of_file"]),
            float(r["share_of_other"]),
            r["other_is_reference"] == "True",
            r["flagged"] == "True",
        )
        for r in rows
    ]


def _compare_here(files: list[Path], out: Path, threshold: float) -> list[Pair]:
    """compare's work, in this process (its hash seed decides the fingerprints)."""
    from copydetect import CopyDetector

    references = reference_files()
    out.mkdir(parents=True, exist_ok=True)
    detector = CopyDetector(
        noise_t=NOISE_TOKENS,
        guarantee_t=GUARANTEE_TOKENS,
        display_t=threshold,
        force_language="python",
        out_file="similarity.html",  # shown in the report: the same wherever the batch is written
        autoopen=False,
        silent=True,
    )
    for path in files:
        detector.add_file(str(path), "testref")
    for path in references:
        detector.add_file(str(path), "ref")
    detector.add_file(str(template_path()), "boilerplate")
    pairs: list[Pair] = []
    html = ""
    if files:
        detector.run()
        matrix = detector.similarity_matrix
        tests, refs = detector.test_files, detector.ref_files
        done: set[frozenset[str]] = set()
        for i, file in enumerate(tests):
            for j, other in enumerate(refs):
                if file == other or frozenset((file, other)) in done or matrix[i, j, 0] < 0:
                    continue
                done.add(frozenset((file, other)))
                share, share_other = float(matrix[i, j, 0]), float(matrix[i, j, 1])
                is_reference = Path(other) in references
                flagged = max(share, share_other) >= threshold
                pairs.append(Pair(file, other, round(share, 3), round(share_other, 3), is_reference, flagged))
        pairs.sort(key=lambda p: (not p.flagged, -max(p.share_of_file, p.share_of_other)))
        with warnings.catch_warnings():  # copydetect 0.5 reads its template with a deprecated call
            warnings.simplefilter("ignore", DeprecationWarning)
            html = detector.generate_html_report(output_mode="return")
    table = io.StringIO()
    writer = csv.writer(table)
    writer.writerow(FIELDS)
    for pair in pairs:
        writer.writerow([getattr(pair, name) for name in FIELDS])
    _write(out / "similarity.csv", table.getvalue())
    _write(out / "similarity.html", html)
    return pairs


def _write(path: Path, text: str) -> None:
    """The file's text, written only when it changed (a resumed batch leaves an unchanged report as it was)."""
    data = text.encode("utf-8")  # as written: csv's rows end in \r\n, which read_text would fold
    try:
        if path.read_bytes() == data:
            return
    except OSError:
        pass
    path.write_bytes(data)


if __name__ == "__main__":  # compare's child: OUT THRESHOLD FILE...
    _compare_here([Path(f) for f in sys.argv[3:]], Path(sys.argv[1]), float(sys.argv[2]))
