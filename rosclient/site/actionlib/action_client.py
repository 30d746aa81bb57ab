"""actionlib's ActionClient and ClientGoalHandle. A goal reaches its server one of two ways:

- over the action's ROS 1 topics when the server speaks them (a program's actionlib server:
  `NAME/status` is a topic): the goal on `NAME/goal`, a cancel on `NAME/cancel`, the goal's status
  from `NAME/status`, its feedback and result from `NAME/feedback` and `NAME/result`, as actionlib's
  client follows them;
- through the lab's action ops otherwise (the lab's own actions, a ROS 2 program's): the lab
  tells the goal's feedback and its end (rosclient/actions.py).

A handle follows the goal's communication state (WAITING_FOR_GOAL_ACK, PENDING, ACTIVE,
WAITING_FOR_RESULT, DONE, ...), calling `transition_cb(handle)` on each change and
`feedback_cb(handle, feedback)` on each feedback.
"""

from __future__ import annotations

import itertools
import threading
import time
from collections.abc import Callable
from typing import Any

import rospy
from actionlib.spec import ActionSpec as Spec
from actionlib_msgs.msg import GoalID, GoalStatus, GoalStatusArray
from rosclient import actions, process

# action_msgs/GoalStatus (the ops') -> actionlib_msgs/GoalStatus
FROM_ROS2 = {
    actions.STATUS_SUCCEEDED: GoalStatus.SUCCEEDED,
    actions.STATUS_CANCELED: GoalStatus.PREEMPTED,
    actions.STATUS_ABORTED: GoalStatus.ABORTED,
    actions.STATUS_ACCEPTED: GoalStatus.ACTIVE,
    actions.STATUS_EXECUTING: GoalStatus.ACTIVE,
    actions.STATUS_CANCELING: GoalStatus.PREEMPTING,
}
TERMINAL = (GoalStatus.PREEMPTED, GoalStatus.SUCCEEDED, GoalStatus.ABORTED, GoalStatus.REJECTED, GoalStatus.RECALLED)
_ids = itertools.count(1)
STATUS_WAIT_S = 10.0  # the longest wait for a topic server's first status, when no timeout says


class CommState:
    WAITING_FOR_GOAL_ACK = 0
    PENDING = 1
    ACTIVE = 2
    WAITING_FOR_RESULT = 3
    WAITING_FOR_CANCEL_ACK = 4
    RECALLING = 5
    PREEMPTING = 6
    DONE = 7
    LOST = 8


# the comm states in which a goal missing from the server's status list is not lost (yet, or any more)
_NOT_LOST = (CommState.WAITING_FOR_GOAL_ACK, CommState.WAITING_FOR_RESULT, CommState.DONE)
# a goal's status -> the comm state it puts the handle in (before its result)
_COMM_OF_STATUS = {
    GoalStatus.PENDING: CommState.PENDING,
    GoalStatus.ACTIVE: CommState.ACTIVE,
    GoalStatus.PREEMPTING: CommState.PREEMPTING,
    GoalStatus.RECALLING: CommState.RECALLING,
}


def get_name_of_constant(C: type, n: int) -> str:
    for name, value in vars(C).items():
        if value == n and not name.startswith("_"):
            return name
    return f"NO_SUCH_STATE_{n}"


def seconds(timeout: Any) -> float | None:
    """actionlib's timeouts: a rospy.Duration (zero: forever) or seconds."""
    value = timeout.to_sec() if hasattr(timeout, "to_sec") else float(timeout or 0.0)
    return None if value <= 0 else value


class ClientGoalHandle:
    def __init__(
        self,
        transition_cb: Callable[[ClientGoalHandle], Any] | None,
        feedback_cb: Callable[[ClientGoalHandle, Any], Any] | None,
    ) -> None:
        self.transition_cb, self.feedback_cb = transition_cb, feedback_cb
        self.comm_state = CommState.WAITING_FOR_GOAL_ACK
        self.status, self.text = GoalStatus.PENDING, ""
        self.result: Any = None
        self.listed = False  # seen in the server's status list (topics)
        self.done = threading.Event()
        self._cancel: Callable[[], None] = lambda: None
        self._lock = threading.RLock()

    # --- what the transport tells ---------------------------------------------------------------
    def _transition(self, state: int) -> None:
        with self._lock:
            if state == self.comm_state or self.comm_state == CommState.DONE:
                return
            self.comm_state = state
        if self.transition_cb is not None:
            self.transition_cb(self)

    def _status(self, status: int, text: str) -> None:
        with self._lock:
            if self.done.is_set():
                return
            self.status, self.text = status, text
        if status in TERMINAL:
            self._transition(CommState.WAITING_FOR_RESULT)
        elif status in _COMM_OF_STATUS:
            self._transition(_COMM_OF_STATUS[status])

    def _feedback(self, feedback: Any) -> None:
        if self.feedback_cb is not None and not self.done.is_set():
            self.feedback_cb(self, feedback)

    def _result(self, status: int, text: str, result: Any) -> None:
        with self._lock:
            if self.done.is_set():
                return
            self.status, self.text, self.result = status, text, result
        self._transition(CommState.WAITING_FOR_RESULT)
        self.done.set()
        self._transition(CommState.DONE)

    # --- actionlib's API ------------------------------------------------------------------------
    def get_comm_state(self) -> int:
        return self.comm_state

    def get_goal_status(self) -> int:
        return self.status

    def get_goal_status_text(self) -> str:
        return self.text

    def get_terminal_state(self) -> int:
        if self.comm_state != CommState.DONE:
            rospy.logwarn(
                "Asking for the terminal state when we're in [%s]", get_name_of_constant(CommState, self.comm_state)
            )
        return self.status

    def get_result(self) -> Any:
        return self.result if self.done.is_set() else None

    def cancel(self) -> None:
        if not self.done.is_set():
            self._cancel()
            self._transition(CommState.WAITING_FOR_CANCEL_ACK)


class _Topics:
    """The action's ROS 1 topics, as a client uses them: goals and cancels out; status, feedback and
    results in, handed to the handles by goal id."""

    def __init__(self, ns: str, spec: Spec) -> None:
        self.spec = spec
        self.handles: dict[str, ClientGoalHandle] = {}
        self.status_seen = threading.Event()
        self.goal_pub = rospy.Publisher(f"{ns}/goal", spec.ActionGoal, queue_size=10)
        self.cancel_pub = rospy.Publisher(f"{ns}/cancel", GoalID, queue_size=10)
        self.subscribers = [
            rospy.Subscriber(f"{ns}/status", GoalStatusArray, self._on_status),
            rospy.Subscriber(f"{ns}/feedback", spec.ActionFeedback, self._on_feedback),
            rospy.Subscriber(f"{ns}/result", spec.ActionResult, self._on_result),
        ]

    def send(self, goal: Any, handle: ClientGoalHandle) -> None:
        stamp = rospy.Time.now()
        goal_id = GoalID(stamp=stamp, id=f"{rospy.get_name()}-{next(_ids)}-{stamp.to_sec():.6f}")
        self.handles[goal_id.id] = handle
        handle._cancel = lambda: self.cancel_pub.publish(GoalID(stamp=rospy.Time(), id=goal_id.id))
        self.goal_pub.publish(self.spec.ActionGoal(header=None, goal_id=goal_id, goal=goal))

    def _on_status(self, message: Any) -> None:
        self.status_seen.set()
        listed = set()
        for status in message.status_list:
            listed.add(status.goal_id.id)
            handle = self.handles.get(status.goal_id.id)
            if handle is not None:
                handle.listed = True
                handle._status(status.status, status.text)
        for goal_id, handle in list(self.handles.items()):
            # a goal the server listed, then dropped before its result: lost, as actionlib's client says
            if goal_id not in listed and handle.listed and handle.comm_state not in _NOT_LOST:
                rospy.logwarn("Transitioning goal to LOST")
                self.handles.pop(goal_id, None)
                handle._result(GoalStatus.LOST, "", None)

    def _on_feedback(self, message: Any) -> None:
        handle = self.handles.get(message.status.goal_id.id)
        if handle is not None:
            handle._status(message.status.status, message.status.text)
            handle._feedback(message.feedback)

    def _on_result(self, message: Any) -> None:
        handle = self.handles.pop(message.status.goal_id.id, None)
        if handle is not None:
            handle._result(message.status.status, message.status.text, message.result)


class ActionClient:
    def __init__(self, ns: str, ActionSpec: Any) -> None:
        self.ns = rospy.resolve_name(ns)
        self.action_class = ActionSpec
        self.spec = Spec(ActionSpec)
        self.handles: list[ClientGoalHandle] = []
        self._topics: _Topics | None = None
        self._checked = False  # whether the server's way (topics or the lab's ops) is known

    def _speaks_topics(self) -> bool:
        """Whether the server is an actionlib server of the action's ROS 1 topics (its status topic is there)."""
        topics = process.connection().call_service("/rosapi/topics", {}, timeout=10).get("topics", [])
        return f"{self.ns}/status" in topics

    def wait_for_server(self, timeout: Any = rospy.Duration()) -> bool:
        ready = process.wait_until(lambda: actions.server_ready(self.ns), seconds(timeout))
        if ready:
            self._choose_way(seconds(timeout))
        return ready

    def _choose_way(self, timeout: float | None) -> None:
        if self._checked:
            return
        self._checked = True
        if self._speaks_topics():
            self._topics = _Topics(self.ns, self.spec)
            self._topics.status_seen.wait(timeout if timeout is not None else STATUS_WAIT_S)  # subscribed

    def wait_for_action_server_to_start(self, timeout: Any = rospy.Duration()) -> bool:
        return self.wait_for_server(timeout)

    def send_goal(
        self,
        goal: Any,
        transition_cb: Callable[[ClientGoalHandle], Any] | None = None,
        feedback_cb: Callable[[ClientGoalHandle, Any], Any] | None = None,
    ) -> ClientGoalHandle:
        handle = ClientGoalHandle(transition_cb, feedback_cb)
        self.handles.append(handle)
        if not self._checked and actions.server_ready(self.ns):
            self._choose_way(STATUS_WAIT_S)
        if self._topics is not None:
            self._topics.send(goal, handle)
            return handle

        def ended(call: actions.GoalCall) -> None:
            handle._result(FROM_ROS2.get(call.status, GoalStatus.LOST), call.error, call.result)

        call = actions.GoalCall(self.ns, self.action_class, goal, handle._feedback, ended)
        handle._cancel = call.cancel
        handle._status(GoalStatus.ACTIVE, "")  # the lab took the goal to its server
        return handle

    def cancel_all_goals(self) -> None:
        if self._topics is not None:
            self._topics.cancel_pub.publish(GoalID(stamp=rospy.Time(), id=""))
            return
        for handle in self.handles:
            handle.cancel()

    def cancel_goals_at_and_before_time(self, time: Any) -> None:
        if self._topics is not None:
            self._topics.cancel_pub.publish(GoalID(stamp=time, id=""))
            return
        self.cancel_all_goals()


def wait_until_done(handle: ClientGoalHandle | None, timeout: Any) -> bool:
    if handle is None:
        return False
    wait = seconds(timeout)
    end = None if wait is None else time.monotonic() + wait
    while not handle.done.wait(0.1 if end is None else max(0.0, min(0.1, end - time.monotonic()))):
        if rospy.is_shutdown() or (end is not None and time.monotonic() >= end):
            return False
    return True
