"""rospy's ROS 1 names (rosclient/site/rospy/names.py), as rosgraph resolves them: global,
private and relative names in the node's namespace, remappings resolved at both ends. The module is
loaded on its own (importing the rospy package would install the program's import finder here)."""

import importlib.util

import pytest

from rosclient import boot


@pytest.fixture
def names():
    spec = importlib.util.spec_from_file_location("rospy_names_under_test", boot.SITE / "rospy" / "names.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_names_resolve_in_the_nodes_namespace_then_remap(names):
    argv = ["talker.py", "__ns:=/foo", "chatter:=/other_chatter", "_rate:=5", "__name:=talker"]
    mappings = names.load_mappings(argv)
    assert mappings == {"__ns": "/foo", "chatter": "/other_chatter", "__name": "talker"}  # not _rate
    names.set_caller_id("/foo/talker", mappings)
    assert (names.get_name(), names.get_namespace()) == ("/foo/talker", "/foo/")
    assert names.resolve_name("utterance") == "/foo/utterance"
    assert names.resolve_name("~topic_name") == "/foo/talker/topic_name"
    assert names.resolve_name("/global//example/") == "/global/example"
    assert names.resolve_name("chatter") == "/other_chatter"  # remapped, resolved at both ends
    assert names.resolve_name("") == "/foo/"
    assert names.resolve_name("x", caller_id="/a/b/node") == "/a/b/x"


def test_namespaces_and_joins(names):
    assert names.make_global_ns("foo") == "/foo/" and names.make_global_ns("") == "/"
    assert names.namespace("/foo/bar/node") == "/foo/bar/" and names.namespace("/node") == "/"
    assert names.ns_join("/foo/", "x") == "/foo/x" and names.ns_join("/", "x") == "/x"
    assert names.ns_join("/foo", "~x") == "~x" and names.ns_join("/foo", "/x") == "/x"
    with pytest.raises(ValueError, match="global"):
        names.make_global_ns("~private")
    assert names.valid_name("/foo/bar_1") and not names.valid_name("/1foo")


def test_before_init_node_names_resolve_in_the_command_lines_namespace(names, monkeypatch):
    monkeypatch.setenv("ROS_NAMESPACE", "/robot")
    assert names.get_ros_namespace(["prog.py"]) == "/robot/"
    assert names.get_ros_namespace(["prog.py", "__ns:=arm"]) == "/arm/"  # the argument wins
