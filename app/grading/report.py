"""A grading report and its formats: text, JSON, Gradescope's results.json, a CSV summary of a batch.

A report is a list of items (points out of max points, and why points were lost) and its pass
rules: the score over all items, and optionally over one section, must reach a mark (%).
An item worth 0 points is reported but not counted ("not counted"). A report that graded nothing
(a file that cannot be loaded) is 0 of its full points in every format. Every format says the seed
and whether it is the public default (PUBLIC_SEED, what every student can run at home).
A fault (a traceback) that cost several items is written once, with the items it cost.
"""

from __future__ import annotations

import csv
import io
import json
from dataclasses import asdict, dataclass, field

PUBLIC_SEED = 0  # the grade's seed when none is given: every student can run this same grade at home
TRACE = "\nTraceback (most recent call last):"  # where an item's detail carries a fault's traceback


def seed_note(seed: int) -> str:
    """What a report says of its seed."""
    if seed == PUBLIC_SEED:
        return f"seed {seed}, the public default: students can run this same grade at home"
    return f"seed {seed}, a private seed"


@dataclass
class Item:
    section: str
    name: str
    points: float
    max_points: float
    detail: str = ""

    @property
    def mark(self) -> str:
        if self.max_points == 0:
            return "not counted"
        return "ok" if self.points == self.max_points else "FAILED"


@dataclass
class Report:
    subject: str  # what was graded (a file, a URL)
    kind: str  # "controller", "services"
    seed: int
    items: list[Item] = field(default_factory=list)
    marks: dict[str, float] = field(default_factory=lambda: {"": 60.0})  # section ("" = all) -> pass mark %
    error: str = ""  # why nothing could be graded (a file that cannot be loaded)
    sha256: str = ""  # of the graded file's bytes: with the seed, says whether a written report is still up to date
    full_points: float = 0.0  # what a grade is out of when it graded nothing (else: the items' total)

    def points_of(self, section: str = "") -> tuple[float, float]:
        items = [i for i in self.items if not section or i.section == section]
        return sum(i.points for i in items), sum(i.max_points for i in items)

    def score_of(self, section: str = "") -> float:
        points, most = self.points_of(section)
        return 100.0 * points / most if most else 0.0

    @property
    def points(self) -> float:
        return self.points_of()[0]

    @property
    def max_points(self) -> float:
        return self.points_of()[1] if self.items else self.full_points

    def faults(self) -> list[tuple[str, list[str]]]:
        """Each traceback in the items' details, once, with the names of the items it cost."""
        found: dict[str, list[str]] = {}
        for i in self.items:
            if TRACE in i.detail:
                found.setdefault(i.detail[i.detail.index(TRACE) + 1 :], []).append(f"{i.section}: {i.name}")
        return list(found.items())

    @property
    def score(self) -> float:
        return self.score_of()

    @property
    def passed(self) -> bool:
        return not self.error and all(self.score_of(section) >= mark for section, mark in self.marks.items())

    def verdict(self) -> str:
        rules = " and ".join(f"{mark:g} % of {section or 'all'} points" for section, mark in self.marks.items())
        return f"score: {self.points:g}/{self.max_points:g} = {self.score:.1f} % (pass: {rules}): " + (
            "PASS" if self.passed else "FAIL"
        )

    def as_dict(self) -> dict:
        return {
            "subject": self.subject,
            "kind": self.kind,
            "seed": self.seed,
            "public_seed": self.seed == PUBLIC_SEED,
            "points": self.points,
            "max_points": self.max_points,
            "score": round(self.score, 1),
            "section_scores": {s: round(self.score_of(s), 1) for s in dict.fromkeys(i.section for i in self.items)},
            "pass_marks": {s or "all": m for s, m in self.marks.items()},
            "passed": self.passed,
            "error": self.error,
            "sha256": self.sha256,
            "full_points": self.full_points,
            "faults": [{"traceback": trace, "items": names} for trace, names in self.faults()],
            "items": [asdict(i) | {"mark": i.mark} for i in self.items],
        }

    @classmethod
    def from_dict(cls, data: dict) -> Report:
        """The report as_dict() wrote (a batch's report read back to resume it)."""
        return cls(
            subject=str(data["subject"]),
            kind=str(data["kind"]),
            seed=int(data["seed"]),
            items=[
                Item(str(i["section"]), str(i["name"]), float(i["points"]), float(i["max_points"]), str(i["detail"]))
                for i in data["items"]
            ],
            marks={("" if s == "all" else s): float(m) for s, m in data["pass_marks"].items()},
            error=str(data.get("error", "")),
            sha256=str(data.get("sha256", "")),
            full_points=float(data.get("full_points", 0.0)),
        )

    def json(self) -> str:
        return json.dumps(self.as_dict(), indent=2)

    def text(self) -> str:
        lines = [f"hri-lab grade ({self.kind}): {self.subject}, {seed_note(self.seed)}"]
        if self.error:
            return "\n".join(lines + [f"NOT GRADED: {self.error}", f"score: 0/{self.max_points:g}: FAIL"])
        lines.append(" points  item")
        for i in self.items:
            lines.append(
                f" {i.points:>4g}/{i.max_points:<3g} {i.section}: {i.name} — {i.mark}"
                + (f": {_short_detail(i.detail)}" if i.detail else "")
            )
        lines.append(self.verdict())
        return "\n".join(lines + self._fault_lines())

    def _fault_lines(self) -> list[str]:
        lines = []
        for trace, names in self.faults():
            lines += ["", f"A fault cost {len(names)} item(s): {', '.join(names)}", trace.rstrip()]
        return lines

    def gradescope(self) -> dict:
        """Gradescope's results.json: the total and one test per item (a report that graded
        nothing: one test, 0 of the full points, saying why)."""
        if self.error:
            return {
                "score": 0.0,
                "output": f"{self.kind} ({seed_note(self.seed)}): not graded: {self.error}",
                "tests": [
                    {
                        "name": f"{self.kind}: not graded",
                        "score": 0.0,
                        "max_score": self.max_points,
                        "output": self.error,
                    }
                ],
            }
        return {
            "score": self.points,
            "output": "\n".join([f"{self.kind} ({seed_note(self.seed)}): {self.verdict()}", *self._fault_lines()]),
            "tests": [
                {
                    "name": f"{i.section}: {i.name}",
                    "score": i.points,
                    "max_score": i.max_points,
                    "output": i.mark + (f": {_short_detail(i.detail)}" if i.detail else ""),
                }
                for i in self.items
            ],
        }


def _short_detail(detail: str) -> str:
    """An item's detail without its traceback (written once, below the items: Report.faults)."""
    return detail[: detail.index(TRACE)] + " (traceback below)" if TRACE in detail else detail


SUMMARY_FIELDS = ("subject", "points", "max_points", "score", "passed", "error", "seed", "public_seed")


def summary_csv(reports: list[Report]) -> str:
    """One line per report (a batch's summary table)."""
    out = io.StringIO()
    writer = csv.writer(out)
    writer.writerow(SUMMARY_FIELDS)
    for r in reports:
        writer.writerow(
            [
                r.subject,
                f"{r.points:g}",
                f"{r.max_points:g}",
                f"{r.score:.1f}",
                "yes" if r.passed else "no",
                r.error.splitlines()[0] if r.error else "",
                r.seed,
                "yes" if r.seed == PUBLIC_SEED else "no",
            ]
        )
    return out.getvalue()
