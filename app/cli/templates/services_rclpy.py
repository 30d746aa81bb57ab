"""services_rclpy.py — the handout's service servers as your own rclpy node.

    hri-lab template services --api rclpy > services_rclpy.py
    hri-lab serve --exercises           # the lab with these services left to you
    hri-lab run services_rclpy.py       # like ros2 run: rclpy works against the lab
    hri-lab service call /divide_ints '{a: 7, b: 2}'      # now answered by this node
    hri-lab grade-services              # grades what your node answers

Each callback fills the response and returns it; an exception fails the call (and ends spin, as in
rclpy). `hri-lab service show /divide_ints` prints a service's .srv. Units: N, Nm, rad.

Unfilled, every handler answers a well-formed wrong value and `hri-lab grade-services` gives
1/15 (add_two_ints, the done example). "Graded:" in each docstring is the rule its item checks
with cases drawn from the grade's seed (docs/students.md, "The services exercises").
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
        """int64 a, int64 b --- int64 sum. (Done: the example.)
        Graded: the exact sum, also near 2^63."""
        response.sum = request.a + request.b
        return response

    def divide_ints(self, request, response):
        """a / b and "Division ok."; for b = 0: 0.0 and "Division by zero!".
        Graded: result = a / b with the message "Division ok."; for b = 0 the message "Division by
        zero!"."""
        return response  # TODO

    def multiply_three(self, request, response):
        """product = a * b * c; outside int64 the call fails (raise ValueError("...")).
        Graded: the exact product; a product outside int64 is a failed call."""
        return response  # TODO

    def echo(self, request, response):
        """out = in (`in` is a Python keyword: the field is request.in_).
        Graded: out = in, for unicode text and the empty string."""
        return response  # TODO

    def login(self, request, response):
        """success for a non-empty user name with magic number 42 ("Welcome, NAME!"), else "Login failed: ...".
        Graded: success for a non-empty user name with 42 ("Welcome, NAME!"), failure for another
        number or an empty name."""
        return response  # TODO

    def planar_torques(self, request, response):
        """tau = J(q)^T F of the 3-link planar arm, links of 1 m.
        Graded: tau = J(q)^T F of the planar arm, 3 values within 1e-4, for [fx, fy] and [fx, fy,
        mz]."""
        response.torques = [0.0, 0.0, 0.0]  # TODO
        return response

    def compute_torques(self, request, response):
        """tau = J(q)^T F (7) at the robot's current q, F at the flange in the base frame.
        Graded: tau = J(q)^T F, 7 values within 1e-4, at the robot's q, for three wrenches."""
        response.torques = [0.0] * 7  # TODO with self.jacobian
        return response

    def compute_wrench(self, request, response):
        """the least-squares F (6) with J^T F = tau.
        Graded: the least-squares F, 6 values within 1e-4, for a tau that J^T F makes and one none
        does."""
        response.force = [0.0] * 6  # TODO
        return response

    def start_cooperative_lifting(self, request, response):
        """f_n_min = request.force, f_n_max = f_n_min + 5; a message that starts, with the force.
        Graded: the lab applies the band when this answers (its /lifting_state must show started,
        f_n_min = force, f_n_max = force + 5), and the message states the force
        ("Cooperative Lifting started with 11.5 N")."""
        response.message = "TODO"
        return response

    def stop_cooperative_lifting(self, request, response):
        """f_n_min = 0; a message that it stopped.
        Graded: the lab stops when this answers (its /lifting_state must show stopped, f_n_min 0),
        and the message says it stopped ("Cooperative Lifting was stopped! The force limit
        was set back to 0 N")."""
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
