"""A lifecycle talker in the style of ROS 2's lifecycle demo: a lifecycle publisher created in
on_configure, a timer that publishes (dropped while the node is not active), each transition said;
its transitions requested from outside (`~/change_state`)."""

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.lifecycle import Node, State, TransitionCallbackReturn
from std_msgs.msg import String


class LifecycleTalker(Node):
    def __init__(self):
        self._pub = None
        self._count = 0
        super().__init__("lc_talker")

    def tick(self):
        msg = String(data=f"Lifecycle HelloWorld #{self._count}")
        self._count += 1
        print(f"active {self._pub.is_activated}", flush=True)
        self._pub.publish(msg)

    def on_configure(self, state: State) -> TransitionCallbackReturn:
        self._pub = self.create_lifecycle_publisher(String, "lifecycle_chatter", 10)
        self.create_timer(0.2, self.tick)
        print(f"on_configure() from {state.label}", flush=True)
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state: State) -> TransitionCallbackReturn:
        print(f"on_activate() from {state.label}", flush=True)
        return super().on_activate(state)

    def on_deactivate(self, state: State) -> TransitionCallbackReturn:
        print("on_deactivate()", flush=True)
        raise RuntimeError("cannot deactivate")  # an ERROR: errorprocessing, then on_error


def main():
    try:
        with rclpy.init():
            rclpy.spin(LifecycleTalker())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == "__main__":
    main()
