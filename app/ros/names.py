"""ROS names: the one helper that turns what a user typed into the absolute name, and the lab's own node."""

LAB_NODE = "/hri_lab"  # the lab as a ROS node (ros2 node list, rosapi, a service's node); its log lines carry node_name(LAB_NODE)


def absolute(name: str) -> str:
    """`add_two_ints`, `/add_two_ints` -> `/add_two_ints` (no trailing or doubled slash)."""
    return "/" + name.strip().strip("/")


def node_name(name: str) -> str:
    """A node as parameters key it: `/cooperative_lifting` -> `cooperative_lifting`."""
    return name.strip().strip("/")
