"""rclpy.lifecycle: managed nodes (ROS 2's node lifecycle): LifecycleNode with its state machine
(unconfigured, inactive, active, finalized and the transitions between them), its on_configure /
on_activate / ... callbacks, lifecycle publishers that publish only while the node is active, and
the services a `ros2 lifecycle` CLI uses (`~/change_state`, `~/get_state`, `~/get_available_states`,
`~/get_available_transitions`) with lifecycle_msgs, and `~/transition_event`."""

from rclpy.lifecycle.managed_entity import ManagedEntity, SimpleManagedEntity
from rclpy.lifecycle.node import LifecycleNode, LifecycleNodeMixin, LifecycleState, TransitionCallbackReturn
from rclpy.lifecycle.publisher import LifecyclePublisher

Node = LifecycleNode
Publisher = LifecyclePublisher
State = LifecycleState

__all__ = [
    "LifecycleNode",
    "LifecycleNodeMixin",
    "LifecyclePublisher",
    "LifecycleState",
    "ManagedEntity",
    "Node",
    "Publisher",
    "SimpleManagedEntity",
    "State",
    "TransitionCallbackReturn",
]
