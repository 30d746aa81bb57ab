"""services_rclpy.py — the handout's service servers as your own rclpy node.

    hri-lab template services --api rclpy > services_rclpy.py
    hri-lab serve --exercises           # the lab with these services left to you
    hri-lab run services_rclpy.py       # like ros2 run: rclpy works against the lab
    hri-lab service call /divide_ints '{a: 7, b: 2}'      # now answered by this node
    hri-lab grade-services              # grades what your node answers

Each callback fills the response and returns it; an exception fails the call (and ends spin, as in
rclpy). `hri-lab service show /divide_ints` prints a service's .srv. Units: N, Nm, rad.
"""

import numpy as np
import rclpy
from hri_lab.msg import FrankaState
from hri_lab.srv import (
    AddTwoInts,
    ComputeTorques,
    ComputeWrench,
    DivideInts,
    Echo,
    Login,
    MultiplyThree,
    PlanarTorques,
    StartCooperativeLifting,
    StopCooperativeLifting,
)
from rclpy.node import Node


class Services(Node):
    def __init__(self):
        super().__init__("services_node")
        self.jacobian = None  # the latest franka_states O_Jac_EE: np.array(msg.O_Jac_EE).reshape(7, 6).T
        self.create_subscription(FrankaState, "/franka_state_controller/franka_states", self.on_state, 1)
        for name, kind in (
            ("add_two_ints", AddTwoInts),
            ("divide_ints", DivideInts),
            ("multiply_three", MultiplyThree),
            ("echo", Echo),
            ("login", Login),
            ("planar_torques", PlanarTorques),
            ("compute_torques", ComputeTorques),
            ("compute_wrench", ComputeWrench),
            ("start_cooperative_lifting", StartCooperativeLifting),
            ("stop_cooperative_lifting", StopCooperativeLifting),
        ):
            self.create_service(kind, name, getattr(self, name))
        self.get_logger().info("node ready: the handout's services")

    def on_state(self, msg):
        self.jacobian = np.array(msg.O_Jac_EE).reshape(7, 6).T

    def add_two_ints(self, request, response):
        """int64 a, int64 b --- int64 sum. (Done: the example.)"""
        response.sum = request.a + request.b
        return response

    def divide_ints(self, request, response):
        """a / b and "Division ok."; for b = 0: 0.0 and "Division by zero!"."""
        return response  # TODO

    def multiply_three(self, request, response):
        """product = a * b * c; outside int64 the call fails (raise ValueError("..."))."""
        return response  # TODO

    def echo(self, request, response):
        """out = in (`in` is a Python keyword: the field is request.in_)."""
        return response  # TODO

    def login(self, request, response):
        """success for a non-empty user name with magic number 42 ("Welcome, NAME!"), else "Login failed: ..."."""
        return response  # TODO

    def planar_torques(self, request, response):
        """tau = J(q)^T F of the 3-link planar arm, links of 1 m."""
        response.torques = [0.0, 0.0, 0.0]  # TODO
        return response

    def compute_torques(self, request, response):
        """tau = J(q)^T F (7) at the robot's current q, F at the flange in the base frame."""
        response.torques = [0.0] * 7  # TODO with self.jacobian
        return response

    def compute_wrench(self, request, response):
        """the least-squares F (6) with J^T F = tau."""
        response.force = [0.0] * 6  # TODO
        return response

    def start_cooperative_lifting(self, request, response):
        """f_n_min = request.force, f_n_max = f_n_min + 5; a message that starts, with the force."""
        response.message = "TODO"
        return response

    def stop_cooperative_lifting(self, request, response):
        """f_n_min = 0; a message that it stopped."""
        response.message = "TODO"
        return response


def main():
    rclpy.init()
    node = Services()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
    node.destroy_node()
    rclpy.try_shutdown()


if __name__ == "__main__":
    main()
