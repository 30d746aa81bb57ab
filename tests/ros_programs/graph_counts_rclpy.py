"""Graph counts (rclpy): a publisher with a matched-event callback (rclpy.event_handler) prints each
event and its subscription count; a second publisher of the same topic is destroyed at once (the
first one still publishes); the count of /joint_states' publishers (the lab's node) is printed."""

import rclpy
from rclpy.event_handler import PublisherEventCallbacks
from rclpy.node import Node
from std_msgs.msg import String


class GraphCounts(Node):
    def __init__(self):
        super().__init__("graph_counts")
        self.pub = self.create_publisher(
            String, "counted", 10, event_callbacks=PublisherEventCallbacks(matched=self.matched)
        )
        spare = self.create_publisher(String, "counted", 10)
        self.destroy_publisher(spare)
        print(f"joint_states publishers: {self.count_publishers('/joint_states')}", flush=True)
        self.create_timer(0.1, lambda: self.pub.publish(String(data="still here")))
        print("graph counts ready", flush=True)

    def matched(self, info):
        print(
            f"matched current={info.current_count} change={info.current_count_change} total={info.total_count}"
            f" count={self.pub.get_subscription_count()}",
            flush=True,
        )


def main():
    rclpy.init()
    try:
        rclpy.spin(GraphCounts())
    except KeyboardInterrupt:
        pass


if __name__ == "__main__":
    main()
