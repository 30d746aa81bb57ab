"""rospy.names: ROS 1's names. A node's name is its namespace and its base name (`__ns:=/foo`, or
$ROS_NAMESPACE, and `__name:=talker` override init_node's); a name resolves as rosgraph's rules say:
`/x` global, `~x` private to the node (/foo/talker/x), `x` relative to the node's namespace
(/foo/x); then a remapping `from:=to` given on the command line replaces it (both ends resolved the
same way). The command line's mappings are read at import, as rospy reads them."""

from __future__ import annotations

import os
import sys

SEP = "/"
PRIV_NAME = "~"
UNNAMED = "/unnamed"


def load_mappings(argv: list[str]) -> dict[str, str]:
    """`from:=to` arguments (not the private parameters `_x:=v`): special keys (`__name`, `__ns`,
    `__log`, ...) and remappings, unresolved."""
    mappings = {}
    for arg in argv[1:]:
        if ":=" not in arg:
            continue
        src, dst = (part.strip() for part in arg.split(":=", 1))
        if src and dst and (src.startswith("__") or not src.startswith("_")):
            mappings[src] = dst
    return mappings


def make_global_ns(ns: str) -> str:
    """`foo` -> `/foo/`: a namespace, absolute, with its trailing slash."""
    if ns.startswith(PRIV_NAME):
        raise ValueError(f"cannot turn {ns!r} into a global name")
    return SEP + ns.strip(SEP) + SEP if ns.strip(SEP) else SEP


def namespace(name: str) -> str:
    """The namespace a name is in, with its trailing slash: `/foo/talker` -> `/foo/`."""
    parent = name.rstrip(SEP).rsplit(SEP, 1)[0]
    return make_global_ns(parent)


def ns_join(ns: str, name: str) -> str:
    if name.startswith((SEP, PRIV_NAME)) or not ns:
        return name
    return ns.rstrip(SEP) + SEP + name if ns != SEP else SEP + name


def canonicalize_name(name: str) -> str:
    """Doubled and trailing slashes gone."""
    if not name or name == SEP:
        return name
    lead = SEP if name.startswith(SEP) else ""
    return lead + SEP.join(part for part in name.split(SEP) if part)


def is_global(name: str) -> bool:
    return name.startswith(SEP)


def is_private(name: str) -> bool:
    return name.startswith(PRIV_NAME)


def _resolve(name: str, caller_id: str, mappings: dict[str, str]) -> str:
    if not name:
        return namespace(caller_id)
    name = canonicalize_name(name)
    if is_global(name):
        resolved = name
    elif is_private(name):
        resolved = canonicalize_name(caller_id + SEP + name[1:])
    else:
        resolved = namespace(caller_id) + name
    return mappings.get(resolved, resolved)


def get_ros_namespace(argv: list[str] | None = None) -> str:
    """`__ns:=` on the command line, else $ROS_NAMESPACE, else the root; absolute, trailing slash."""
    ns = load_mappings(sys.argv if argv is None else argv).get("__ns") or os.environ.get("ROS_NAMESPACE", "")
    return make_global_ns(ns)


_mappings: dict[str, str] = load_mappings(sys.argv)
_resolved_mappings: dict[str, str] = {}
_caller_namespace = get_ros_namespace()
_caller_id = UNNAMED
_initialized = [False]


def initialize_mappings(caller_id: str) -> None:
    """The command line's remappings, both ends resolved for the node `caller_id`."""
    _resolved_mappings.clear()
    for src, dst in _mappings.items():
        if not src.startswith("__"):
            _resolved_mappings[_resolve(src, caller_id, {})] = _resolve(dst, caller_id, {})


def set_caller_id(caller_id: str, mappings: dict[str, str] | None = None) -> None:
    """The node's full name, set by init_node (with the mappings of its argv when it was given one)."""
    global _caller_id, _caller_namespace
    if mappings is not None:
        _mappings.clear()
        _mappings.update(mappings)
    _caller_id = caller_id
    _caller_namespace = namespace(caller_id)
    _initialized[0] = True
    initialize_mappings(caller_id)


def get_name() -> str:
    """The node's full name (`/unnamed` before init_node)."""
    return _caller_id


get_caller_id = get_name


def get_namespace() -> str:
    """The node's namespace, absolute with its trailing slash (`/`, `/foo/`)."""
    return _caller_namespace


def get_mappings() -> dict[str, str]:
    return dict(_mappings)


def get_resolved_mappings() -> dict[str, str]:
    return dict(_resolved_mappings)


def resolve_name(name: str, caller_id: str | None = None) -> str:
    """`name` made absolute for the node `caller_id` (this node by default), then remapped."""
    if caller_id is None:
        caller = _caller_id if _initialized[0] else _caller_namespace + UNNAMED.strip(SEP)
    else:
        caller = caller_id
    return _resolve(name, caller, _resolved_mappings)


def remap_name(name: str, caller_id: str | None = None, resolved: bool = True) -> str:
    """A resolved name's remapping (itself when none)."""
    return _resolved_mappings.get(name, name)


def valid_name(name: str) -> bool:
    """A ROS 1 graph resource name: letters, digits, '_' and '/', '~' first, not starting with a digit."""
    import re

    return bool(re.fullmatch(r"[~/]?([A-Za-z][\w]*)?(/[A-Za-z][\w]*)*/?", name))


initialize_mappings(_caller_namespace + UNNAMED.strip(SEP))  # names made before init_node are remapped too
