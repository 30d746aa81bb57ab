"""A grading report and its formats: text, JSON, Gradescope's results.json, a CSV summary of a batch.

A report is a list of items (points out of max points, and why points were lost) and its pass
rules: the score over all items, and optionally over one section, must reach a mark (%).
An item worth 0 points is reported but not counted ("not counted").
"""

from __future__ import annotations

import csv
import io
import json
from dataclasses import asdict, dataclass, field


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
        return self.points_of()[1]

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
            "points": self.points,
            "max_points": self.max_points,
            "score": round(self.score, 1),
            "section_scores": {s: round(self.score_of(s), 1) for s in dict.fromkeys(i.section for i in self.items)},
            "pass_marks": {s or "all": m for s, m in self.marks.items()},
            "passed": self.passed,
            "error": self.error,
            "sha256": self.sha256,
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
        )

    def json(self) -> str:
        return json.dumps(self.as_dict(), indent=2)

    def text(self) -> str:
        lines = [f"hri-lab grade ({self.kind}): {self.subject}, seed {self.seed}"]
        if self.error:
            return "\n".join(lines + [f"NOT GRADED: {self.error}", "score: 0: FAIL"])
        lines.append(" points  item")
        for i in self.items:
            lines.append(
                f" {i.points:>4g}/{i.max_points:<3g} {i.section}: {i.name} — {i.mark}"
                + (f": {i.detail}" if i.detail else "")
            )
        lines.append(self.verdict())
        return "\n".join(lines)

    def gradescope(self) -> dict:
        """Gradescope's results.json: the total and one test per item."""
        if self.error:
            return {"score": 0.0, "output": f"not graded: {self.error}", "tests": []}
        return {
            "score": self.points,
            "output": self.verdict(),
            "tests": [
                {
                    "name": f"{i.section}: {i.name}",
                    "score": i.points,
                    "max_score": i.max_points,
                    "output": i.mark + (f": {i.detail}" if i.detail else ""),
                }
                for i in self.items
            ],
        }


SUMMARY_FIELDS = ("subject", "points", "max_points", "score", "passed", "error")


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
            ]
        )
    return out.getvalue()
