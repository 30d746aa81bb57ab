"""actionlib's ActionServer: goals come from two sides and are one set of handles.

- ROS 1 action clients (actionlib's own, roslibjs's and roslibpy's ActionClient through rosbridge)
  speak the action's topics: they publish `NAME/goal` (XActionGoal) and `NAME/cancel`
  (actionlib_msgs/GoalID) and read `NAME/status` (GoalStatusArray, at 5 Hz and on each change),
  `NAME/feedback` and `NAME/result`, as actionlib's server publishes them;
- the lab and its other clients (HTTP, the page, `hri-lab action`, ROS 2 clients) reach the same
  server through rosbridge's action ops (rosclient/actions.py): the lab lists it as an action.

Goal and cancel callbacks run on the server's own thread, in the order the goals came.
"""

from __future__ import annotations

import queue
import threading
import time
import uuid
from collections.abc import Callable
from typing import Any

import rospy
from actionlib.server_goal_handle import (
    ABORTED,
    PREEMPTED,
    RECALLED,
    REJECTED,
    SUCCEEDED,
    TERMINAL,
    ServerGoalHandle,
)
from actionlib.spec import ActionSpec as Spec
from actionlib_msgs.msg import GoalID, GoalStatusArray
from rosclient import actions, process

STATUS_FREQUENCY_HZ = 5.0  # actionlib's status_frequency
STATUS_LIST_TIMEOUT_S = 5.0  # how long an ended goal stays in the status list
# actionlib's ends as action_msgs/GoalStatus (what the lab's action ops carry)
_TO_ROS2 = {
    SUCCEEDED: actions.STATUS_SUCCEEDED,
    PREEMPTED: actions.STATUS_CANCELED,
    RECALLED: actions.STATUS_CANCELED,
    ABORTED: actions.STATUS_ABORTED,
    REJECTED: actions.STATUS_ABORTED,
}


def nop_cb(goal_handle: ServerGoalHandle) -> None:
    pass


class ActionServer:
    def __init__(
        self,
        ns: str,
        ActionSpec: Any,
        goal_cb: Callable[[ServerGoalHandle], Any],
        cancel_cb: Callable[[ServerGoalHandle], Any] = nop_cb,
        auto_start: bool = True,
    ) -> None:
        self.ns = rospy.resolve_name(ns)
        self.spec = Spec(ActionSpec)
        self.goal_callback, self.cancel_callback = goal_cb, cancel_cb
        self.lock = threading.RLock()
        self.status_list: list[ServerGoalHandle] = []  # every goal tracked, as actionlib's status list
        self.last_cancel_ns = 0  # the stamp of the newest cancel of all goals up to a time
        self.started = False
        self._inbox: queue.Queue[Callable[[], None]] = queue.Queue()
        if auto_start:
            self.start()

    def start(self) -> None:
        with self.lock:
            if self.started:
                return
            self.started = True
        ns = self.ns
        self.status_pub = rospy.Publisher(f"{ns}/status", GoalStatusArray, latch=True, queue_size=50)
        self.result_pub = rospy.Publisher(f"{ns}/result", self.spec.ActionResult, latch=True, queue_size=50)
        self.feedback_pub = rospy.Publisher(f"{ns}/feedback", self.spec.ActionFeedback, queue_size=50)
        threading.Thread(target=self._work, daemon=True, name=f"actionlib{ns}").start()
        self.goal_sub = rospy.Subscriber(f"{ns}/goal", self.spec.ActionGoal, self._goal_message)
        self.cancel_sub = rospy.Subscriber(f"{ns}/cancel", GoalID, self._cancel_message)
        self.serving = actions.ActionServing(ns, self.spec.action_class, self._goal_op, self._cancel_op)
        threading.Thread(target=self._publish_status_loop, daemon=True, name=f"actionlib-status{ns}").start()

    # --- in: goals and cancels, queued for the server's thread -----------------------------------
    def _work(self) -> None:
        while not rospy.is_shutdown():
            try:
                job = self._inbox.get(timeout=0.5)
            except queue.Empty:
                continue
            try:
                job()
            except Exception as exc:  # noqa: BLE001 - actionlib logs a failing callback and goes on
                rospy.logerr("Exception in an action server callback of %s: %s", self.ns, exc)

    def _goal_message(self, action_goal: Any) -> None:
        self._inbox.put(lambda: self._new_goal(action_goal.goal_id, action_goal.goal, None))

    def _cancel_message(self, goal_id: Any) -> None:
        self._inbox.put(lambda: self._cancel(goal_id))

    def _goal_op(self, served: actions.ServedGoal) -> None:
        goal_id = GoalID(stamp=_stamp(time.time_ns()), id=str(served.id))
        self._inbox.put(lambda: self._new_goal(goal_id, served.request, served))

    def _cancel_op(self, served: actions.ServedGoal) -> None:
        self._inbox.put(lambda: self._cancel(GoalID(id=str(served.id))))

    def _new_goal(self, goal_id: Any, goal: Any, origin: actions.ServedGoal | None) -> None:
        with self.lock:
            if not goal_id.stamp.to_nsec():  # actionlib: a goal sent without a time is stamped on arrival
                goal_id.stamp = rospy.Time.now()
            if not goal_id.id:
                goal_id.id = f"{rospy.get_name()}-{uuid.uuid4().hex[:8]}-{goal_id.stamp.to_sec():.3f}"
            if any(h.status.goal_id.id == goal_id.id for h in self.status_list):  # a goal sent twice is one
                return
            handle = ServerGoalHandle(self, self.spec.ActionGoal(header=None, goal_id=goal_id, goal=goal), origin)
            self.status_list.append(handle)
            if goal_id.stamp.to_nsec() <= self.last_cancel_ns:
                handle.set_canceled(None, "This goal handle was canceled by the action server because its "
                                    "timestamp is before the timestamp of the last cancel request")  # fmt: skip
                return
        self.goal_callback(handle)

    def _cancel(self, goal_id: Any) -> None:
        """actionlib's cancel rules: an empty id and a zero stamp cancel every goal; an id, that goal;
        a stamp, every goal up to it."""
        stamp_ns = goal_id.stamp.to_nsec()
        with self.lock:
            chosen = [
                h
                for h in self.status_list
                if (not goal_id.id and not stamp_ns)
                or h.status.goal_id.id == goal_id.id
                or (stamp_ns and h.status.goal_id.stamp.to_nsec() <= stamp_ns)
            ]
            if stamp_ns > self.last_cancel_ns:
                self.last_cancel_ns = stamp_ns
        for handle in chosen:
            if handle.set_cancel_requested():
                self.publish_status()
                self.cancel_callback(handle)

    # --- out: status, feedback, results -----------------------------------------------------------
    def publish_status(self) -> None:
        now = time.monotonic()
        with self.lock:
            self.status_list[:] = [
                h for h in self.status_list if h.destroy_time is None or now - h.destroy_time <= STATUS_LIST_TIMEOUT_S
            ]
            status_list = [h.status for h in self.status_list]
        if not rospy.core.topics_closed():
            self.status_pub.publish(GoalStatusArray(header=_header(), status_list=status_list))

    def _publish_status_loop(self) -> None:
        while not rospy.is_shutdown():
            self.publish_status()
            if process.shutdown_event.wait(1.0 / STATUS_FREQUENCY_HZ):
                return

    def publish_result(self, handle: ServerGoalHandle, result: Any) -> None:
        if rospy.core.topics_closed():  # the node has shut down: nobody to tell
            return
        result = result if result is not None else self.spec.Result()
        with self.lock:
            handle.destroy_time = time.monotonic()
            status = handle.status
        if handle.origin is not None:
            if status.status == REJECTED:
                handle.origin.reject(status.text or "rejected by the action server")
            else:
                handle.origin.finish(_TO_ROS2[status.status], result)
        self.result_pub.publish(self.spec.ActionResult(header=_header(), status=status, result=result))
        self.publish_status()

    def publish_feedback(self, handle: ServerGoalHandle, feedback: Any) -> None:
        if handle.status.status in TERMINAL or rospy.core.topics_closed():
            return
        if handle.origin is not None:
            handle.origin.publish_feedback(feedback)
        self.feedback_pub.publish(
            self.spec.ActionFeedback(header=_header(), status=handle.status, feedback=feedback)
        )


def _stamp(ns: int) -> Any:
    return rospy.Time(0, ns)


def _header() -> Any:
    from std_msgs.msg import Header

    return Header(stamp=rospy.Time.now())
