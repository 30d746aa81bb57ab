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
        entry = {
            "name": joint.get("name"),
            "type": joint.get("type"),
            "parent": joint.find("parent").get("link"),
            "child": joint.find("child").get("link"),
        }
        if limit is not None:
            for key in ("lower", "upper", "velocity", "effort"):
                if limit.get(key) is not None:
                    entry[key] = float(limit.get(key))
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
