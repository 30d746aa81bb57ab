"""app/ros/params.py: ROS 2 parameters — declared types, ranges, choices and read-only flags with
rclcpp's refusals, dump and load as `ros2 param` writes them, the nodes' own parameters through
`remote`, and a parameter file's limits."""

import pytest
import yaml

from app.ros import params
from app.ros.params import Parameter, ParameterRefused, ParameterServer, parse_parameter_file, read_parameter_file

DECLARED = [
    Parameter("cooperative_lifting", "mu", "double", 0.5, "friction", range=(0.0, 2.0)),
    Parameter("cooperative_lifting", "controller", "string", "sp", "law", choices=("sp", "patch")),
    Parameter("human", "steps", "integer", 3, "steps"),
    Parameter("hri_lab", "version", "string", "1", "build", read_only=True),
]


def server() -> ParameterServer:
    return ParameterServer(DECLARED, lab=None)  # no declaration here applies to or reads the world


def test_get_and_set_by_either_spelling_of_the_node():
    lab = server()
    lab.set("/cooperative_lifting", "mu", 1)  # an integer for a double (JSON has one number type)
    assert lab.get("cooperative_lifting", "mu") == 1.0
    assert isinstance(lab.get("cooperative_lifting", "mu"), float)
    assert lab.typed("/cooperative_lifting", "mu") == ("double", 1.0)


@pytest.mark.parametrize(
    ("node", "name", "value", "reason"),
    [
        (
            "cooperative_lifting",
            "mu",
            "fast",
            "Wrong parameter type, parameter {mu} is of type {double}, setting it to {string} is not allowed.",
        ),
        ("cooperative_lifting", "mu", True, "is of type {double}, setting it to {bool}"),
        ("cooperative_lifting", "mu", 3.0, "Parameter {mu} doesn't comply with floating point range."),
        ("cooperative_lifting", "controller", "pid", "Parameter {controller} must be one of sp, patch."),
        ("human", "steps", 2.5, "is of type {integer}, setting it to {double}"),
        ("hri_lab", "version", "2", "parameter 'version' cannot be set because it is read-only"),
        ("human", "nothing", 1, "parameter 'nothing' cannot be set because it was not declared"),
    ],
)
def test_refusals_are_rclcpp_s(node, name, value, reason):
    lab = server()
    with pytest.raises(ParameterRefused) as refused:
        lab.set(node, name, value)
    assert reason in str(refused.value)
    assert lab.get("cooperative_lifting", "mu") == 0.5  # nothing changed


def test_force_sets_a_read_only_parameter_and_describe_gives_the_declaration():
    lab = server()
    lab.set("hri_lab", "version", "2", force=True)
    assert lab.get("hri_lab", "version") == "2"
    assert lab.describe("cooperative_lifting", "mu") == {
        "node": "cooperative_lifting",
        "name": "mu",
        "type": "double",
        "description": "friction",
        "read_only": False,
        "default": 0.5,
        "min_value": 0.0,
        "max_value": 2.0,
    }
    with pytest.raises(ParameterRefused) as missing:
        lab.get("human", "nothing")
    assert missing.value.status == 404


def test_dump_and_load_round_trip_with_one_result_per_parameter():
    lab = server()
    text = lab.dump("cooperative_lifting")
    assert yaml.safe_load(text) == {"cooperative_lifting": {"ros__parameters": {"mu": 0.5, "controller": "sp"}}}
    results = lab.load("cooperative_lifting:\n  ros__parameters:\n    mu: 0.8\n    controller: pid\n")
    assert [(r["name"], r["successful"]) for r in results] == [("mu", True), ("controller", False)]
    assert lab.get("cooperative_lifting", "mu") == 0.8
    assert "must be one of" in results[1]["reason"]
    with pytest.raises(ParameterRefused, match="no ros__parameters"):
        lab.load("cooperative_lifting: 3\n")


class NodeParameters:
    """A node that declares its own parameters, reached as `remote` is (rosbridge's node_params)."""

    def __init__(self) -> None:
        self.values = {"talker": {"rate": 10}}

    def nodes(self):
        return list(self.values)

    def names(self, node):
        return list(self.values[node])

    def get(self, node, names):
        return [self.values[node].get(n) for n in names]

    def set(self, node, name, value):
        self.values[node][name] = value

    def describe(self, node, name):
        return {"node": node, "name": name, "type": "integer"}


def test_a_node_s_own_parameters_join_the_lab_s():
    lab = server()
    lab.remote = NodeParameters()
    assert lab.remote_node("/talker")
    assert not lab.remote_node("human")
    assert ("talker", "rate") in lab.names()
    assert lab.has("talker", "rate")
    assert not lab.has("talker", "other")
    lab.set("/talker", "rate", 20)
    assert lab.get("talker", "rate") == 20
    assert lab.typed("talker", "rate") == ("integer", 20)
    assert yaml.safe_load(lab.dump("talker")) == {"talker": {"ros__parameters": {"rate": 20}}}
    with pytest.raises(ParameterRefused, match="Parameter not set"):
        lab.get("talker", "other")


def test_a_parameter_file_s_limits(tmp_path, monkeypatch):
    assert parse_parameter_file("a:\n  ros__parameters: {x: 1}\n") == {"a": {"ros__parameters": {"x": 1}}}
    for text, reason in (
        ("a: &x [1]\nb: *x\n", "no YAML aliases"),
        ("[" * (params.MAX_FILE_DEPTH + 1) + "]" * (params.MAX_FILE_DEPTH + 1), "nests at most"),
        ("a: [\n", "invalid YAML"),
        ("x" * (params.MAX_FILE_BYTES + 1), "at most"),
    ):
        with pytest.raises(ParameterRefused, match=reason):
            parse_parameter_file(text)
    (tmp_path / "bag.mcap").write_bytes(b"\x89MCAP\xff\xfe")
    for path, reason in (
        (tmp_path, "a folder"),
        (tmp_path / "none.yaml", "no such file"),
        (tmp_path / "bag.mcap", "binary"),
    ):
        with pytest.raises(ParameterRefused, match=reason):
            read_parameter_file(path)


def test_a_number_parameter_reads_as_a_float_and_a_string_one_is_refused():
    lab = server()
    lab.set("cooperative_lifting", "mu", 1)
    assert lab.number("/cooperative_lifting", "mu") == 1.0
    assert isinstance(lab.number("cooperative_lifting", "mu"), float)
    assert lab.number("human", "steps") == 3.0
    with pytest.raises(ParameterRefused, match="'controller' is not a number: string"):
        lab.number("cooperative_lifting", "controller")


def test_a_validator_applies_nothing():
    read = Parameter("cooperative_lifting", "alpha", "double", 0.5, "gain", read=lambda world: 0.5)
    with pytest.raises(RuntimeError, match="only validates"):
        ParameterServer([read], lab=None).get("cooperative_lifting", "alpha")
