"""Service introspection (rclpy, as ros2/demos' introspection demo configures it): a client with
CONTENTS and a service with METADATA on /introspected_sum; the client calls every 0.3 s."""

import rclpy
from example_interfaces.srv import AddTwoInts
from rclpy.node import Node
from rclpy.qos import qos_profile_system_default
from rclpy.service_introspection import ServiceIntrospectionState


class Introspected(Node):
    def __init__(self):
        super().__init__("introspected")
        self.srv = self.create_service(AddTwoInts, "introspected_sum", self.add)
        self.srv.configure_introspection(
            self.get_clock(), qos_profile_system_default, ServiceIntrospectionState.METADATA
        )
        self.cli = self.create_client(AddTwoInts, "introspected_sum")
        self.cli.configure_introspection(
            self.get_clock(), qos_profile_system_default, ServiceIntrospectionState.CONTENTS
        )
        self.create_timer(0.3, self.call)

    def add(self, request, response):
        response.sum = request.a + request.b
        return response

    def call(self):
        if self.cli.service_is_ready():
            self.cli.call_async(AddTwoInts.Request(a=2, b=3)).add_done_callback(
                lambda f: print(f"sum {f.result().sum}", flush=True)
            )


def main():
    rclpy.init()
    try:
        rclpy.spin(Introspected())
    except KeyboardInterrupt:
        pass


if __name__ == "__main__":
    main()
