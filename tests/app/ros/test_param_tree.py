"""app/ros/param_tree.py: ROS 1's parameter server — one tree of names, namespaces as dicts, the
master's getParamNames and searchParam, read-only names and the limits."""

import pytest

from app.ros import param_tree
from app.ros.param_tree import ParamError, ParameterTree, canonical


def test_canonical_names_as_the_master_keys_them():
    assert canonical("a/b", "/ns") == "/ns/a/b"
    assert canonical("/a/b/") == "/a/b"
    assert canonical("/") == "/"
    for bad in ("", "  ", "a b", "/a//b", "x" * 300, 3):
        with pytest.raises(ParamError):
            canonical(bad)


def test_a_dict_sets_a_subtree_and_a_namespace_reads_as_a_dict():
    tree = ParameterTree()
    tree.set("/robot/gains", {"k_n": 0.005, "k_t": 0.1})
    tree.set("/robot/name", "panda")
    assert tree.get("/robot") == {"gains": {"k_n": 0.005, "k_t": 0.1}, "name": "panda"}
    assert tree.names() == ["/robot/gains/k_n", "/robot/gains/k_t", "/robot/name"]
    assert tree.get("/robot/none", "default") == "default"
    assert not tree.has("/robot/none")


def test_a_value_read_is_a_copy():
    tree = ParameterTree()
    tree.set("/list", [1, 2])
    tree.get("/list").append(3)
    assert tree.get("/list") == [1, 2]


def test_delete_a_leaf_a_namespace_and_the_root():
    tree = ParameterTree()
    tree.set("/a/b", 1)
    tree.set("/a/c", 2)
    assert tree.delete("/a/b")
    assert not tree.delete("/a/b")
    assert tree.names() == ["/a/c"]
    assert tree.delete("/")
    assert tree.names() == []


def test_search_finds_the_nearest_name_up_from_the_namespace():
    tree = ParameterTree()
    tree.set("/robot_description", "<robot/>")
    tree.set("/ns/robot_description", "<inner/>")
    assert tree.search("robot_description", "/ns/node") == "/ns/robot_description"
    assert tree.search("robot_description", "/other") == "/robot_description"
    assert tree.search("missing", "/ns") is None
    with pytest.raises(ParamError):
        tree.search("/", "/ns")


def test_a_read_only_name_is_read_never_set_or_deleted_and_survives_the_root():
    tree = ParameterTree(read_only={"/robot_description": ("<robot/>", "the lab's URDF")})
    assert tree.get("/robot_description") == "<robot/>"
    for action in (lambda: tree.set("/robot_description", "x"), lambda: tree.set("/robot_description/sub", 1)):
        with pytest.raises(ParamError, match="read-only \\(the lab's URDF\\)"):
            action()
    with pytest.raises(ParamError, match="read-only"):
        tree.delete("/robot_description")
    tree.set("/", {"other": 1})
    assert tree.get("/") == {"other": 1, "robot_description": "<robot/>"}
    tree.delete("/")
    assert tree.names() == ["/robot_description"]


def test_values_are_json_and_the_tree_is_bounded(monkeypatch):
    tree = ParameterTree()
    for bad in (float("nan"), object(), "x" * (param_tree.MAX_VALUE_CHARS + 1)):
        with pytest.raises(ParamError):
            tree.set("/bad", bad)
    with pytest.raises(ParamError, match="only be set to a dict"):
        tree.set("/", 3)
    monkeypatch.setattr(param_tree, "MAX_ENTRIES", 2)
    tree.set("/a", 1)
    tree.set("/b", 2)
    with pytest.raises(ParamError, match="at most 2 parameters"):
        tree.set("/c", 3)
    tree.set("/a", 10)  # replacing a leaf adds none
    assert tree.names() == ["/a", "/b"]
    assert tree.get("/a") == 10
