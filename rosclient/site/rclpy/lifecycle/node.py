"""rclpy.lifecycle.node: LifecycleNode and its state machine, as ROS 2's node lifecycle design has it."""

from __future__ import annotations

import time
from typing import Any, NamedTuple

from rclpy import _endpoints
from rclpy.lifecycle.managed_entity import ManagedEntity, TransitionCallbackReturn
from rclpy.lifecycle.publisher import LifecyclePublisher
from rclpy.node import Node
from rclpy.qos import QoSProfile


class LifecycleState(NamedTuple):
    label: str
    state_id: int


STATES = {
    0: "unknown", 1: "unconfigured", 2: "inactive", 3: "active", 4: "finalized",
    10: "configuring", 11: "cleaningup", 12: "shuttingdown", 13: "activating", 14: "deactivating",
    15: "errorprocessing",
}  # fmt: skip
# transition id -> (its label, from, through, on success, on failure, the callback's name)
TRANSITIONS = {
    1: ("configure", 1, 10, 2, 1, "on_configure"),
    2: ("cleanup", 2, 11, 1, 2, "on_cleanup"),
    3: ("activate", 2, 13, 3, 2, "on_activate"),
    4: ("deactivate", 3, 14, 2, 3, "on_deactivate"),
    5: ("shutdown", 1, 12, 4, 1, "on_shutdown"),
    6: ("shutdown", 2, 12, 4, 2, "on_shutdown"),
    7: ("shutdown", 3, 12, 4, 3, "on_shutdown"),
}
RESULT_IDS = {"configure": 10, "cleanup": 20, "activate": 30, "deactivate": 40, "shutdown": 50}  # + 0/1/2


def _state(state_id: int) -> LifecycleState:
    return LifecycleState(STATES[state_id], state_id)


class LifecycleNodeMixin(ManagedEntity):
    """The state machine and its services; a Node subclass mixes it in (LifecycleNode)."""

    def _init_lifecycle(self, enable_communication_interface: bool = True) -> None:
        self._state_id = 1
        self._managed: list[ManagedEntity] = []
        if not enable_communication_interface:
            self._transition_events = None
            return
        from lifecycle_msgs.msg import TransitionEvent
        from lifecycle_msgs.srv import ChangeState, GetAvailableStates, GetAvailableTransitions, GetState

        node: Any = self
        self._transition_events = node.create_publisher(TransitionEvent, "~/transition_event", 10)
        node.create_service(ChangeState, "~/change_state", self._on_change_state)
        node.create_service(GetState, "~/get_state", self._on_get_state)
        node.create_service(GetAvailableStates, "~/get_available_states", self._on_get_available_states)
        node.create_service(GetAvailableTransitions, "~/get_available_transitions", self._on_get_transitions)
        node.create_service(GetAvailableTransitions, "~/get_transition_graph", self._on_get_graph)

    # --- the services -------------------------------------------------------------------------------
    def _on_change_state(self, request: Any, response: Any) -> Any:
        wanted = request.transition.id
        if not wanted and request.transition.label:
            wanted = next((i for i in self._available() if TRANSITIONS[i][0] == request.transition.label), 0)
        response.success = self._trigger(wanted) == TransitionCallbackReturn.SUCCESS
        return response

    def _on_get_state(self, request: Any, response: Any) -> Any:
        response.current_state.id = self._state_id
        response.current_state.label = STATES[self._state_id]
        return response

    def _on_get_available_states(self, request: Any, response: Any) -> Any:
        from lifecycle_msgs.msg import State

        response.available_states = [State(id=i, label=label) for i, label in STATES.items()]
        return response

    def _descriptions(self, ids: list[int]) -> list[Any]:
        from lifecycle_msgs.msg import State, Transition, TransitionDescription

        return [
            TransitionDescription(
                transition=Transition(id=i, label=TRANSITIONS[i][0]),
                start_state=State(id=TRANSITIONS[i][1], label=STATES[TRANSITIONS[i][1]]),
                goal_state=State(id=TRANSITIONS[i][2], label=STATES[TRANSITIONS[i][2]]),
            )
            for i in ids
        ]

    def _on_get_transitions(self, request: Any, response: Any) -> Any:
        response.available_transitions = self._descriptions(self._available())
        return response

    def _on_get_graph(self, request: Any, response: Any) -> Any:
        response.available_transitions = self._descriptions(sorted(TRANSITIONS))
        return response

    # --- the state machine -------------------------------------------------------------------------
    def _available(self) -> list[int]:
        return [i for i, t in TRANSITIONS.items() if t[1] == self._state_id]

    def _publish_event(self, transition_id: int, label: str, start: int, goal: int) -> None:
        if self._transition_events is None:
            return
        from lifecycle_msgs.msg import State, Transition, TransitionEvent

        self._transition_events.publish(
            TransitionEvent(
                timestamp=time.time_ns(),
                transition=Transition(id=transition_id, label=label),
                start_state=State(id=start, label=STATES[start]),
                goal_state=State(id=goal, label=STATES[goal]),
            )
        )

    def _call(self, name: str, state: LifecycleState) -> TransitionCallbackReturn:
        try:
            result = getattr(self, name)(state)
        except Exception as exc:  # a callback that raises is an ERROR, as rclpy treats it
            node: Any = self
            node.get_logger().error(f"Caught exception in {name}: {exc!r}")
            return TransitionCallbackReturn.ERROR
        return TransitionCallbackReturn(int(result)) if result is not None else TransitionCallbackReturn.ERROR

    def _trigger(self, transition_id: int) -> TransitionCallbackReturn:
        if transition_id not in self._available():
            node: Any = self
            node.get_logger().warning(
                f"Unable to start transition {transition_id} from current state {STATES[self._state_id]}: "
                "Transition is not registered."
            )
            return TransitionCallbackReturn.FAILURE
        label, start, through, success, failure, callback = TRANSITIONS[transition_id]
        self._state_id = through
        self._publish_event(transition_id, label, start, through)
        result = self._call(callback, _state(start))
        if result == TransitionCallbackReturn.SUCCESS:
            goal = success
        elif result == TransitionCallbackReturn.FAILURE:
            goal = failure
        else:
            self._state_id = 15
            handled = self._call("on_error", _state(start))
            goal = 1 if handled == TransitionCallbackReturn.SUCCESS else 4
        self._state_id = goal
        self._publish_event(RESULT_IDS[label] + (result - 97), label, through, goal)
        return result

    def trigger_configure(self) -> TransitionCallbackReturn:
        return self._trigger(1)

    def trigger_cleanup(self) -> TransitionCallbackReturn:
        return self._trigger(2)

    def trigger_activate(self) -> TransitionCallbackReturn:
        return self._trigger(3)

    def trigger_deactivate(self) -> TransitionCallbackReturn:
        return self._trigger(4)

    def trigger_shutdown(self) -> TransitionCallbackReturn:
        return self._trigger({1: 5, 2: 6, 3: 7}.get(self._state_id, 5))

    # --- the default callbacks: the managed entities follow the node -------------------------------
    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._each("on_configure", state)

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._each("on_cleanup", state)

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._each("on_shutdown", state)

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._each("on_activate", state)

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._each("on_deactivate", state)

    def on_error(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._each("on_error", state)

    def _each(self, name: str, state: LifecycleState) -> TransitionCallbackReturn:
        for entity in self._managed:
            result = getattr(entity, name)(state)
            if result != TransitionCallbackReturn.SUCCESS:
                return TransitionCallbackReturn(int(result))
        return TransitionCallbackReturn.SUCCESS

    def add_managed_entity(self, entity: ManagedEntity) -> None:
        self._managed.append(entity)

    @property
    def _current_state(self) -> LifecycleState:
        return _state(self._state_id)


class LifecycleNode(LifecycleNodeMixin, Node):
    def __init__(self, node_name: str, *, enable_communication_interface: bool = True, **kwargs: Any) -> None:
        Node.__init__(self, node_name, **kwargs)
        self._init_lifecycle(enable_communication_interface)

    def create_lifecycle_publisher(self, msg_type: type, topic: str, qos_profile: QoSProfile | int,
                                   **kwargs: Any) -> LifecyclePublisher:
        publisher = LifecyclePublisher(self, msg_type, topic, qos_profile)
        _endpoints.ready(publisher._endpoint)  # no event handlers: the pairs the lab's news made are not kept
        self.publishers.append(publisher)
        self.add_managed_entity(publisher)
        return publisher
