"""A URDF file checked as ROS's `check_urdf` (urdfdom) checks it, each error with its line.

`parse_urdf(text)` answers a `UrdfModel` (the robot's name, its links, its joints and the tree they
make) or raises `UrdfError` naming the line and what was expected there. The rules are urdfdom's
(`urdf_parser/src/model.cpp`, `joint.cpp`): a `<robot name=...>` root, named and unique links and
joints, a known joint type, a parent and a child link that exist, `<limit>` with `effort` and
`velocity` on a revolute or prismatic joint (`lower`/`upper` default to 0), numbers where numbers
go, exactly one root link. Two that urdfdom lets through are refused too, because a viewer or a
controller cannot use them: `lower > upper`, and a link with two parents (which is how a cycle
shows).

`tree_text(model)` is what `check_urdf` prints for a file it accepts. The XML is read by lxml,
which keeps each element's line (`sourceline`). Joint positions are in rad (revolute, continuous)
or m (prismatic)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from lxml import etree

JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
MOVABLE_TYPES = ("revolute", "continuous", "prismatic")  # one slider each (joint_state_publisher's)
MAX_FILE_BYTES = 10_000_000
MAX_INDENT = 64  # levels of the tree indented in `tree_text`; deeper ones are printed at this indent, their depth said
XACRO = "http://www.ros.org/wiki/xacro"  # the xacro namespace: its macros are not URDF


class UrdfError(ValueError):
    """What is wrong with a URDF and where: `line` (1-based, None for the file as a whole)."""

    def __init__(self, message: str, line: int | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.line = line

    def located(self, source: str) -> str:
        """`FILE:LINE: message`, the compiler's way."""
        return f"{source}:{self.line}: {self.message}" if self.line else f"{source}: {self.message}"


@dataclass(frozen=True)
class Link:
    name: str
    line: int


@dataclass(frozen=True)
class Joint:
    """A joint: `lower_rad_or_m`/`upper_rad_or_m` are the file's limits (None when it gives none)."""

    name: str
    type: str
    parent: str
    child: str
    line: int
    lower_rad_or_m: float | None = None
    upper_rad_or_m: float | None = None
    axis: tuple[float, float, float] = (1.0, 0.0, 0.0)

    @property
    def movable(self) -> bool:
        return self.type in MOVABLE_TYPES

    def slider_range(self) -> tuple[float, float]:
        """The range a slider offers: the file's limits; a continuous joint's is ±pi, as
        joint_state_publisher's."""
        if self.type == "continuous":
            return -math.pi, math.pi
        return float(self.lower_rad_or_m or 0.0), float(self.upper_rad_or_m or 0.0)


@dataclass
class UrdfModel:
    name: str
    links: list[Link]
    joints: list[Joint]
    root: str
    children: dict[str, list[str]] = field(default_factory=dict)  # link -> child links, by joint name

    def movable_joints(self) -> list[Joint]:
        return [j for j in self.joints if j.movable]


def _line(element) -> int:
    return int(element.sourceline or 0)


def _float(element, attribute: str, what: str, default: float | None = None) -> float | None:
    text = element.get(attribute)
    if text is None:
        return default
    try:
        value = float(text)
    except ValueError:
        raise UrdfError(f'{what}: {attribute}="{text}" is not a number', _line(element)) from None
    if not math.isfinite(value):
        raise UrdfError(f'{what}: {attribute}="{text}" is not a finite number', _line(element))
    return value


def _vector(element, attribute: str, what: str) -> tuple[float, float, float] | None:
    text = element.get(attribute)
    if text is None:
        return None
    parts = text.split()
    try:
        values = tuple(float(p) for p in parts)
    except ValueError:
        values = ()
    if len(values) != 3 or not all(math.isfinite(v) for v in values):
        raise UrdfError(f'{what}: {attribute}="{text}" is not three numbers like "0 0 1"', _line(element))
    return values[0], values[1], values[2]


def _name(element, kind: str) -> str:
    name = (element.get("name") or "").strip()
    if not name:
        raise UrdfError(f'<{kind}> has no name: expected <{kind} name="...">', _line(element))
    return name


def _joint(element) -> Joint:
    name = _name(element, "joint")
    what = f"joint '{name}'"
    line = _line(element)
    joint_type = element.get("type")
    if joint_type is None:
        raise UrdfError(f'{what} has no type: expected type="{"|".join(JOINT_TYPES)}"', line)
    if joint_type not in JOINT_TYPES:
        raise UrdfError(f'{what} has unknown type "{joint_type}": expected one of {", ".join(JOINT_TYPES)}', line)
    links = {}
    for end in ("parent", "child"):
        tag = element.find(end)
        if tag is None or not (tag.get("link") or "").strip():
            raise UrdfError(f'{what} has no {end} link: expected <{end} link="..."/>', line)
        links[end] = tag.get("link").strip()
    origin = element.find("origin")
    if origin is not None:
        _vector(origin, "xyz", f"{what} <origin>")
        _vector(origin, "rpy", f"{what} <origin>")
    axis = (1.0, 0.0, 0.0)
    axis_tag = element.find("axis")
    if axis_tag is not None and joint_type not in ("fixed", "floating"):
        axis = _vector(axis_tag, "xyz", f"{what} <axis>") or axis
        if not any(axis):
            raise UrdfError(
                f'{what} <axis>: xyz="0 0 0" has no direction: expected a unit vector like "0 0 1"', _line(axis_tag)
            )
    lower = upper = None
    limit = element.find("limit")
    if limit is None and joint_type in ("revolute", "prismatic"):
        raise UrdfError(
            f'{what} is {joint_type} but has no <limit>: expected <limit lower="..." upper="..." effort="..." velocity="..."/>',
            line,
        )
    if limit is not None:
        where = f"{what} <limit>"
        lower = _float(limit, "lower", where, 0.0)
        upper = _float(limit, "upper", where, 0.0)
        for required in ("effort", "velocity"):
            if limit.get(required) is None:
                raise UrdfError(f'{where} has no {required}: expected {required}="..." (a number)', _line(limit))
            _float(limit, required, where)
        if joint_type in ("revolute", "prismatic") and lower is not None and upper is not None and lower > upper:
            raise UrdfError(f"{where}: lower={lower:g} is above upper={upper:g}: expected lower <= upper", _line(limit))
    return Joint(name, joint_type, links["parent"], links["child"], line, lower, upper, axis)


def _robot(text: str | bytes) -> tuple[etree._Element, str]:
    """The <robot> element of a URDF's text and its name, or `UrdfError`: not XML, over the size
    bound, another root, no name, a xacro file."""
    data = text.encode("utf-8") if isinstance(text, str) else text
    if len(data) > MAX_FILE_BYTES:
        raise UrdfError(f"the file is over {MAX_FILE_BYTES // 1_000_000} MB: not a URDF")
    parser = etree.XMLParser(resolve_entities=False, no_network=True, remove_comments=True, huge_tree=False)
    try:
        root = etree.fromstring(data, parser)
    except etree.XMLSyntaxError as exc:
        raise UrdfError(f"not XML: {exc.msg}", exc.lineno or None) from None
    if root.tag != "robot":
        raise UrdfError(f'the root element is <{root.tag}>: expected <robot name="...">', _line(root))
    robot_name = (root.get("name") or "").strip()
    if not robot_name:
        raise UrdfError('<robot> has no name: expected <robot name="...">', _line(root))

    if any(str(e.tag).startswith(f"{{{XACRO}}}") for e in root.iter()):  # declaring the namespace alone is common
        raise UrdfError(
            "a xacro file (<xacro:...> elements): hri-lab reads plain URDF; expand it first with ROS's "
            "xacro (`xacro robot.urdf.xacro > robot.urdf`)",
            _line(root),
        )
    return root, robot_name


def parse_urdf(text: str | bytes) -> UrdfModel:
    """The model of a URDF's text, or `UrdfError` with the line of the first thing wrong."""
    root, robot_name = _robot(text)
    links: dict[str, Link] = {}
    for element in root.iterfind("link"):
        name = _name(element, "link")
        if name in links:
            raise UrdfError(f"link '{name}' is not unique: it is also at line {links[name].line}", _line(element))
        links[name] = Link(name, _line(element))
    if not links:
        raise UrdfError('no <link> in the robot: expected at least one <link name="...">', _line(root))

    joints: dict[str, Joint] = {}
    parent_joint: dict[str, Joint] = {}  # child link -> the joint that holds it
    for element in root.iterfind("joint"):
        joint = _joint(element)
        if joint.name in joints:
            raise UrdfError(
                f"joint '{joint.name}' is not unique: it is also at line {joints[joint.name].line}", joint.line
            )
        for end, link in (("parent", joint.parent), ("child", joint.child)):
            if link not in links:
                raise UrdfError(
                    f"joint '{joint.name}': its {end} link '{link}' does not exist: expected one of {', '.join(links)}",
                    joint.line,
                )
        if joint.parent == joint.child:
            raise UrdfError(f"joint '{joint.name}' joins link '{joint.child}' to itself", joint.line)
        if joint.child in parent_joint:
            other = parent_joint[joint.child]
            raise UrdfError(
                f"link '{joint.child}' has two parents: joint '{joint.name}' and joint '{other.name}' "
                f"(line {other.line}); a URDF is a tree, each link has at most one parent joint",
                joint.line,
            )
        joints[joint.name] = joint
        parent_joint[joint.child] = joint

    roots = [name for name in links if name not in parent_joint]
    if len(roots) > 1:
        raise UrdfError(
            f"two root links: '{roots[0]}' (line {links[roots[0]].line}) and '{roots[1]}' "
            f"(line {links[roots[1]].line}): expected one, the others joined to it by joints",
            links[roots[1]].line,
        )
    children: dict[str, list[str]] = {name: [] for name in links}
    for joint in sorted(joints.values(), key=lambda j: j.name):  # urdfdom's order: its joints map, by name
        children[joint.parent].append(joint.child)
    reached = set()
    stack = roots[:1]
    while stack:
        link = stack.pop()
        reached.add(link)
        stack.extend(children[link])
    unreached = [name for name in links if name not in reached]
    if unreached:  # each link has at most one parent, so what the root cannot reach hangs off a cycle
        cycle = _cycle(unreached[0], parent_joint)
        path = "".join(f"{j.parent} -[{j.name}, line {j.line}]-> " for j in cycle) + cycle[0].parent
        raise UrdfError(
            f"the joints make a cycle: {path}; expected a tree" + ("" if roots else " (there is no root link)"),
            max(j.line for j in cycle),  # the last of them in the file: most often the one added by mistake
        )
    return UrdfModel(robot_name, list(links.values()), list(joints.values()), roots[0], children)


def _cycle(start: str, parent_joint: dict[str, Joint]) -> list[Joint]:
    """The joints of the cycle above `start` (every link on it has a parent), parent to child."""
    seen: list[str] = []
    link = start
    while link not in seen:
        seen.append(link)
        link = parent_joint[link].parent
    cycle = []
    at = link
    while True:
        joint = parent_joint[at]
        cycle.append(joint)
        at = joint.parent
        if at == link:
            break
    return cycle[::-1]


def parse_urdf_file(path: str | Path) -> UrdfModel:
    """`parse_urdf` of a file; a file that cannot be read is a `UrdfError` too."""
    try:
        data = Path(path).read_bytes()
    except OSError as exc:
        raise UrdfError(f"cannot read the file: {exc.strerror}") from None
    return parse_urdf(data)


def tree_text(model: UrdfModel) -> str:
    """What `check_urdf` prints for a file it accepts (urdfdom's check_urdf.cpp)."""
    lines = [
        f"robot name is: {model.name}",
        "---------- Successfully Parsed XML ---------------",
        f"root Link: {model.root} has {len(model.children[model.root])} child(ren)",
    ]

    def below(link: str, level: int) -> list[tuple[str, int, int]]:  # (child, its level, its count), last first
        return [(child, level + 2, count) for count, child in enumerate(model.children[link], start=1)][::-1]

    stack = below(model.root, 0)  # depth first without recursion: a chain of 40,000 links is a file like any
    while stack:
        link, level, count = stack.pop()
        depth = f" (depth {level // 2})" if level > 2 * MAX_INDENT else ""
        lines.append("  " * min(level, 2 * MAX_INDENT) + f"child({count}):  {link}{depth}")
        stack += below(link, level)
    return "\n".join(lines) + "\n"


def joints_text(model: UrdfModel) -> str:
    """The joints, their types and limits, one a line (beyond check_urdf: what a slider will offer)."""
    lines = ["---------- Joints ---------------"]
    for joint in model.joints:
        unit = "m" if joint.type == "prismatic" else "rad"
        limits = ""
        if joint.movable:
            low, high = joint.slider_range()
            limits = f"  [{low:g}, {high:g}] {unit}" + ("  (continuous: ±pi)" if joint.type == "continuous" else "")
        lines.append(f"{joint.name} ({joint.type}): {joint.parent} -> {joint.child}{limits}  line {joint.line}")
    return "\n".join(lines) + "\n"
