"""The Panda's links and joints with their limits, as `check_urdf` shows them (served at GET /robot)."""

import xml.etree.ElementTree as ElementTree

from sim.robot.assets import panda_urdf


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
