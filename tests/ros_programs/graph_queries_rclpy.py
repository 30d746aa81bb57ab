"""rclpy's graph queries and next-layer names: what the node sees of its own topic and service by
name and ROS 2 type, its name among the graph's nodes, rclpy.Parameter at the top level, the QoS
and event names a program imports."""

import rclpy
from example_interfaces.srv import AddTwoInts
from rclpy.event_handler import UnsupportedEventTypeError  # noqa: F401 - importable, as in rclpy
from rclpy.node import Node
from rclpy.qos import QoSLivelinessPolicy
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node("graph_queries", namespace="/lab")
    node.create_publisher(String, "chatter", 10)
    node.create_service(AddTwoInts, "adder", lambda request, response: response)
    topics = dict(node.get_topic_names_and_types())
    print("topic", topics.get("/lab/chatter"), flush=True)
    services = dict(node.get_service_names_and_types())
    print("service", services.get("/lab/adder"), flush=True)
    print("node", ("graph_queries", "/lab") in node.get_node_names_and_namespaces(), flush=True)
    published = dict(node.get_publisher_names_and_types_by_node("graph_queries", "/lab"))
    print("by node", published.get("/lab/chatter"), flush=True)
    print("parameter", rclpy.Parameter("x", value=3).value, flush=True)
    print("liveliness", QoSLivelinessPolicy.AUTOMATIC.name, flush=True)
    node.destroy_node()
    rclpy.shutdown()


if __name__ == "__main__":
    main()
