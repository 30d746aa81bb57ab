"""Keys to twist (rclpy): the keys of argv ('w' forward, 's' back, 'a'/'d' turn) become Twists on
/key_twist, scaled by the parameters linear_speed and angular_speed (settable while it runs)."""

import sys

import rclpy
from geometry_msgs.msg import Twist
from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor, SetParametersResult
from rclpy.node import Node

KEYS = {"w": (1, 0), "s": (-1, 0), "a": (0, 1), "d": (0, -1)}


class KeyTwist(Node):
    def __init__(self, keys):
        super().__init__("keytwist_param")
        self.declare_parameter("linear_speed", 0.1)
        self.declare_parameter(
            "angular_speed",
            0.5,
            ParameterDescriptor(
                description="rad/s per key press",
                floating_point_range=[FloatingPointRange(from_value=0.0, to_value=2.0)],
            ),
        )
        self.add_on_set_parameters_callback(self.check)
        self.publisher = self.create_publisher(Twist, "key_twist", 10)
        self.keys, self.index = keys, 0
        self.create_timer(0.2, self.tick)

    def check(self, parameters):
        for p in parameters:
            if p.name == "linear_speed" and p.value > 5.0:
                return SetParametersResult(successful=False, reason="linear_speed above 5 m/s is unsafe")
        return SetParametersResult(successful=True)

    def tick(self):
        key = self.keys[self.index % len(self.keys)]
        self.index += 1
        linear, angular = KEYS[key]
        msg = Twist()
        msg.linear.x = linear * self.get_parameter("linear_speed").value
        msg.angular.z = angular * self.get_parameter("angular_speed").get_parameter_value().double_value
        self.publisher.publish(msg)
        print(f"key {key}: linear.x={msg.linear.x:g} angular.z={msg.angular.z:g}", flush=True)


def main():
    rclpy.init()
    node = KeyTwist(rclpy.remove_ros_args(sys.argv)[1] if len(rclpy.remove_ros_args(sys.argv)) > 1 else "w")
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass


if __name__ == "__main__":
    main()
