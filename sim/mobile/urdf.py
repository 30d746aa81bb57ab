"""The base's URDF (the /robot_description parameter of the mobile world): turtlebot3_burger.urdf's
tree (base_footprint -> base_link -> the wheels, the caster, base_scan) with simple shapes for its
meshes; its numbers come from the base's and the scanner's figures (sim/mobile/base.py, lidar.py)."""

from __future__ import annotations

from functools import cache

from sim.mobile.base import BaseSpec
from sim.mobile.messages import BASE_LINK, FOOTPRINT, SCAN_FRAME, WHEEL_JOINTS, WHEEL_LINKS, static_transforms

BODY_SIZE = (0.140, 0.140, 0.143)  # m, the Burger's stacked plates
WHEEL_WIDTH = 0.018  # m


def _origin(xyz, rpy=(0.0, 0.0, 0.0)) -> str:
    return f'<origin xyz="{xyz[0]:g} {xyz[1]:g} {xyz[2]:g}" rpy="{rpy[0]:g} {rpy[1]:g} {rpy[2]:g}"/>'


def _link(name: str, geometry: str, origin: str, mass: float) -> str:
    return (
        f'  <link name="{name}">\n'
        f"    <visual>{origin}<geometry>{geometry}</geometry></visual>\n"
        f"    <collision>{origin}<geometry>{geometry}</geometry></collision>\n"
        f'    <inertial><origin xyz="0 0 0"/><mass value="{mass:g}"/>'
        f'<inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>\n'
        f"  </link>\n"
    )


@cache
def burger_urdf() -> str:
    r = BaseSpec().wheel_radius
    joints = {child: (parent, xyz) for parent, child, xyz in static_transforms()}
    sx, sy, sz = BODY_SIZE
    parts = ['<?xml version="1.0"?>\n<robot name="turtlebot3_burger">\n', f'  <link name="{FOOTPRINT}"/>\n']
    parts.append(_link(BASE_LINK, f'<box size="{sx:g} {sy:g} {sz:g}"/>', _origin((-0.032, 0, sz / 2)), 0.825))
    parts.append(
        f'  <joint name="base_joint" type="fixed"><parent link="{FOOTPRINT}"/><child link="{BASE_LINK}"/>'
        f"{_origin(joints[BASE_LINK][1])}</joint>\n"
    )
    for joint, link in zip(WHEEL_JOINTS, WHEEL_LINKS):
        cylinder = f'<cylinder radius="{r:g}" length="{WHEEL_WIDTH:g}"/>'
        parts.append(_link(link, cylinder, _origin((0, 0, 0), (-1.57079632679, 0, 0)), 0.0285))
        parts.append(
            f'  <joint name="{joint}" type="continuous"><parent link="{BASE_LINK}"/><child link="{link}"/>'
            f'{_origin(joints[link][1])}<axis xyz="0 1 0"/></joint>\n'
        )
    parts.append(_link(SCAN_FRAME, '<cylinder radius="0.035" length="0.03"/>', _origin((0, 0, -0.01)), 0.114))
    parts.append(
        f'  <joint name="scan_joint" type="fixed"><parent link="{BASE_LINK}"/><child link="{SCAN_FRAME}"/>'
        f"{_origin(joints[SCAN_FRAME][1])}</joint>\n"
    )
    parts.append("</robot>\n")
    return "".join(parts)
