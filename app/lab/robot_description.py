"""The Panda's URDF: its text, the ROS parameter `/robot_description` (as robot_state_publisher's
launch files set it; GET /robot/description), and its links and joints with their limits, as
`check_urdf` shows them (GET /robot)."""

import xml.etree.ElementTree as ElementTree
from functools import cache

from sim.robot.assets import panda_urdf

ROBOT_DESCRIPTION = "/robot_description"
ROBOT_DESCRIPTION_WHY = "the lab's robot, the Panda's URDF; `hri-lab urdf view FILE.urdf` serves your own"


@cache
def robot_description_text() -> str:
    """The URDF the simulation loads, as its file has it."""
    return panda_urdf().read_text(encoding="utf-8")


def robot_description() -> dict:
    """Links and joints of the URDF the simulation loads (fingers included, as in the file)."""
    root = ElementTree.parse(panda_urdf()).getroot()
    joints = []
    for joint in root.findall("joint"):
        limit = joint.find("limit")
        entry: dict[str, str | float | None] = {
            "name": joint.get("name"),
            "type": joint.get("type"),
            "parent": _link(joint, "parent"),
            "child": _link(joint, "child"),
        }
        if limit is not None:
            for key in ("lower", "upper", "velocity", "effort"):
                if (value := limit.get(key)) is not None:
                    entry[key] = float(value)
        joints.append(entry)
    children = {j["child"] for j in joints}
    links = [link.get("name") for link in root.findall("link")]
    return {
        "name": root.get("name"),
        "root_link": next(name for name in links if name not in children),
        "links": links,
        "joints": joints,
        "end_effector": "panda_link8",
    }


def _link(joint: ElementTree.Element, end: str) -> str:
    """The link a joint's <parent> or <child> names (a URDF's joint has both: urdf_check's rule)."""
    element = joint.find(end)
    link = element.get("link") if element is not None else None
    if link is None:
        raise ValueError(f"joint {joint.get('name')!r} of the lab's URDF has no <{end} link=...>")
    return link
