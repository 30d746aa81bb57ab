"""The lab as a node: one name (`LAB_NODE`), the node's fully qualified name wherever nodes are
listed and its logger's name on the lines the lab logs itself."""

import re
from pathlib import Path

from app.ros.names import LAB_NODE, node_name

APP = Path(__file__).resolve().parents[3] / "app"


def test_the_lab_node_is_named_once():
    defined = [
        f"{path.relative_to(APP.parent)}:{number}"
        for path in APP.rglob("*.py")
        for number, line in enumerate(path.read_text().splitlines(), 1)
        if re.match(r"\s*LAB_NODE\s*[:=]", line)
    ]
    assert len(defined) == 1 and defined[0].startswith("app/ros/names.py:"), defined
    assert LAB_NODE == "/hri_lab"
    assert node_name(LAB_NODE) == "hri_lab"


def test_the_lab_is_listed_and_logs_under_that_name(client, lab):
    assert client.get("/services/echo").json()["node"] == LAB_NODE  # a service the lab itself provides
    started = [line for line in lab.rosout.recent() if line.msg == "the simulation started"]
    assert [line.node for line in started] == [node_name(LAB_NODE)]
