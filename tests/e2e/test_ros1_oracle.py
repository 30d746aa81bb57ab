"""Checked against real ROS 1 (bench/ros1_oracle.py): the course's rospy programs run under Debian's
roscore and rospy (`make ros1`, which `make test` runs) and under the lab, and what a user sees —
printed lines, the graph, parameters, service answers — is the same but for the differences listed
with their reasons (docs/ros-programs.md, "Checked against real ROS 1")."""

import pytest

from bench import ros1_oracle as oracle


@pytest.fixture(scope="module")
def sides():
    missing = oracle.available()
    assert missing is None, f"make test installs real ROS 1 (make ros1); missing: {missing}"
    with oracle.sides() as pair:
        yield pair


@pytest.mark.parametrize("case", oracle.CASES, ids=lambda case: case.name)
def test_a_ros1_program_shows_what_real_ros1_shows(sides, case):
    real, lab = sides
    assert oracle.differences(case, oracle.run_case(real, case), oracle.run_case(lab, case)) == []
