"""The services exercises as the handouts define them: each test is one gradable item, in the
grader's order (the torques while the robot is at rest, start before stop)."""

import pytest

from app.grading.services import EXERCISES, grade_exercise


@pytest.mark.parametrize("exercise", EXERCISES, ids=[e.service.strip("/") for e in EXERCISES])
def test_exercise(grading, exercise):
    item = grade_exercise(grading, exercise)
    assert item.points == item.max_points, item.detail
