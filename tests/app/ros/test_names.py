"""app/ros/names.py: a user's name made absolute, a node's name as parameters key it."""

import pytest

from app.ros.names import absolute, node_name


@pytest.mark.parametrize("typed", ["add_two_ints", "/add_two_ints", " /add_two_ints/ ", "//add_two_ints"])
def test_absolute_has_one_leading_slash_and_no_trailing_one(typed):
    assert absolute(typed) == "/add_two_ints"


def test_a_nested_name_keeps_its_inner_slashes():
    assert absolute("rosapi/topics") == "/rosapi/topics"


@pytest.mark.parametrize("typed", ["/cooperative_lifting", "cooperative_lifting", " cooperative_lifting/ "])
def test_node_name_drops_the_slashes(typed):
    assert node_name(typed) == "cooperative_lifting"
