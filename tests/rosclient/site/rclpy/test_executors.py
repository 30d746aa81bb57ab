"""rclpy's executors (rosclient/site/rclpy/executors.py) in this process, over a recording
connection that stands for the lab's (what the program sends is kept, what the lab sends is fed to
the handlers): a wait round takes every ready entity once — ONE message per subscription — so a busy
subscription never starves a service or a timer; coroutine callbacks run as tasks that await
futures; create_task; spin_until_future_complete's timeout; MultiThreadedExecutor keeps callback
groups' rules."""

from __future__ import annotations

import threading

import pytest


def spin_until(executor, predicate, rounds: int = 100) -> None:
    """spin_once until `predicate()` (each round may run one pending task first, as in rclpy)."""
    for _ in range(rounds):
        if predicate():
            return
        executor.spin_once(timeout_sec=0.1)
    assert predicate()


def test_a_round_takes_one_message_per_subscription_and_every_other_ready_entity(rclpy):
    from example_interfaces.srv import AddTwoInts
    from rclpy.executors import SingleThreadedExecutor
    from std_msgs.msg import String

    node = rclpy.create_node("round", start_parameter_services=False)
    ran: list[str] = []
    node.create_subscription(String, "chatter", lambda msg: ran.append(f"msg {msg.data}"), 10)

    def add(request, response):
        ran.append("service")
        response.sum = request.a + request.b
        return response

    node.create_service(AddTwoInts, "add", add)
    guard = node.create_guard_condition(lambda: ran.append("guard"))
    for i in range(5):
        rclpy.connection.publish("/chatter", {"data": str(i)})
    rclpy.connection.call("/add", "call:1", {"a": 2, "b": 3})
    guard.trigger()
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    for _ in range(3):
        executor.spin_once(timeout_sec=0)
    # one round: the subscription's oldest message, the guard condition, the service (rclpy's order)
    assert ran == ["msg 0", "guard", "service"]
    assert rclpy.connection.sent[-1] == {
        "op": "service_response",
        "id": "call:1",
        "service": "/add",
        "values": {"sum": 5},
        "result": True,
    }
    for _ in range(4):
        executor.spin_once(timeout_sec=0)
    assert ran[3:] == ["msg 1", "msg 2", "msg 3", "msg 4"]
    executor.spin_once(timeout_sec=0)  # nothing ready: returns at once
    assert len(ran) == 7


def test_a_subscription_always_ready_does_not_starve_a_service(rclpy):
    """A callback slower than the publisher (its queue never empties): a request is served after at
    most one more message, not after the queue."""
    from example_interfaces.srv import AddTwoInts
    from rclpy.executors import SingleThreadedExecutor
    from std_msgs.msg import String

    node = rclpy.create_node("busy", start_parameter_services=False)
    handled: list[str] = []

    def image(msg):
        handled.append(msg.data)
        for i in range(3):  # three more arrive while this one is handled
            rclpy.connection.publish("/image_raw", {"data": f"{msg.data}.{i}"})

    node.create_subscription(String, "image_raw", image, 10)
    node.create_service(AddTwoInts, "add", lambda request, response: response)
    rclpy.connection.publish("/image_raw", {"data": "first"})
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    executor.spin_once(timeout_sec=0)
    rclpy.connection.call("/add", "call:7", {"a": 1, "b": 1})
    for _ in range(2):
        executor.spin_once(timeout_sec=0)
    assert [m["id"] for m in rclpy.connection.sent if m["op"] == "service_response"] == ["call:7"]
    assert len(handled) <= 2


def test_coroutine_callbacks_await_futures_and_create_task_runs_in_spin(rclpy):
    from example_interfaces.srv import AddTwoInts
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.task import Future

    node = rclpy.create_node("tasks", start_parameter_services=False)
    client = node.create_client(AddTwoInts, "add")
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    steps: list[str] = []

    async def call_twice():
        first = await client.call_async(AddTwoInts.Request(a=1, b=2))
        steps.append(f"first {first.sum}")
        second = await client.call_async(AddTwoInts.Request(a=first.sum, b=10))
        steps.append(f"second {second.sum}")
        return second.sum

    task = executor.create_task(call_twice)
    executor.spin_until_future_complete(task, timeout_sec=0.2)  # no answer: the timeout ends it
    assert not task.done() and steps == [] and len(rclpy.connection.calls) == 1
    rclpy.connection.calls[0].set_result((True, {"sum": 3}))
    executor.spin_until_future_complete(task, timeout_sec=0.2)
    assert steps == ["first 3"] and len(rclpy.connection.calls) == 2
    rclpy.connection.calls[1].set_result((True, {"sum": 13}))
    executor.spin_until_future_complete(task, timeout_sec=5)
    assert task.done() and task.result() == 13 and steps == ["first 3", "second 13"]

    waited = Future()
    timer_ran: list[object] = []

    async def on_timer():
        timer.cancel()
        timer_ran.append(await waited)

    timer = node.create_timer(0.01, on_timer)
    spin_until(executor, timer.is_canceled)  # the callback began: it awaits the future
    for _ in range(3):
        executor.spin_once(timeout_sec=0.05)
    assert timer_ran == []
    waited.set_result("late")
    spin_until(executor, lambda: timer_ran == ["late"])


def test_an_exception_in_a_callback_leaves_spin(rclpy):
    from rclpy.executors import SingleThreadedExecutor

    node = rclpy.create_node("raising", start_parameter_services=False)

    def fail():
        raise ValueError("in the callback")

    node.create_timer(0.001, fail)
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    with pytest.raises(ValueError, match="in the callback"):
        executor.spin_once(timeout_sec=5)


@pytest.mark.parametrize("reentrant", [False, True])
def test_multithreaded_executor_keeps_callback_groups_rules(rclpy, reentrant):
    """Two timers in one group: a mutually exclusive group never runs both at once (the second
    waits for the first, which waits for it in vain); a reentrant one runs them together."""
    from rclpy.callback_groups import MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
    from rclpy.executors import MultiThreadedExecutor

    node = rclpy.create_node("groups", start_parameter_services=False)
    group = ReentrantCallbackGroup() if reentrant else MutuallyExclusiveCallbackGroup()
    together = threading.Barrier(2, timeout=1.0)
    outcomes: list[str] = []
    lock = threading.Lock()
    running = [0]
    most = [0]

    def callback(timer_index: int) -> None:
        timers[timer_index].cancel()
        with lock:
            running[0] += 1
            most[0] = max(most[0], running[0])
        try:
            together.wait()
            outcomes.append("met")
        except threading.BrokenBarrierError:
            outcomes.append("alone")
        with lock:
            running[0] -= 1

    timers = [node.create_timer(0.01, lambda i=i: callback(i), callback_group=group) for i in range(2)]
    executor = MultiThreadedExecutor(num_threads=2)
    executor.add_node(node)
    try:
        from rclpy.task import Future

        done = Future()
        watcher = threading.Thread(target=lambda: executor.spin_until_future_complete(done, timeout_sec=10))
        watcher.start()
        from tests.waiting import wait_for

        wait_for(lambda: len(outcomes) == 2, timeout=30)
    finally:
        executor.shutdown()
        watcher.join(timeout=30)
    if reentrant:
        assert outcomes == ["met", "met"] and most[0] == 2
    else:
        assert most[0] == 1 and outcomes[0] == "alone"
