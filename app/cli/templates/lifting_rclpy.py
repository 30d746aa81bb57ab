"""lifting_rclpy.py — the lifting application of Exercise 16 as an rclpy node: it reads F_ext, runs
your SP law and commands the robot with a Twist (the lab's command watchdog stops the robot when
the commands stop), and it provides the start/stop services.

    hri-lab template node --api rclpy > lifting_rclpy.py
    hri-lab run lifting_rclpy.py
    hri-lab service call /start_cooperative_lifting '{force: 10}'

As it is, it runs and commands zero twist. Units: N, Nm, m/s, rad/s.
"""

import math

import numpy as np
import rclpy
from geometry_msgs.msg import Twist, WrenchStamped
from hri_lab.msg import FrankaState
from hri_lab.srv import StartCooperativeLifting, StopCooperativeLifting
from rclpy.node import Node

PARAMS = {}  # @lab-defaults


def lifting_law(wrench_ee, f_n_min, p):
    """The SP method: F_ext (6, flange frame, filtered) -> twist_ee (6, flange frame)."""
    # TODO the steps of the handout: band on f_n, slip on f_t, comply with m_c, saturate
    return np.zeros(6)


class Lifting(Node):
    def __init__(self):
        super().__init__("cooperative_lifting")
        for name, value in PARAMS.items():
            self.declare_parameter(name, value)  # `hri-lab param set /cooperative_lifting k_n 0.01` while it runs
        self.running, self.f_n_min = False, 0.0
        self.rotation, self.filtered, self.stamp = None, None, None
        self.command = self.create_publisher(Twist, "/cartesian_velocity_controller/command", 1)
        self.create_subscription(FrankaState, "/franka_state_controller/franka_states", self.on_state, 1)
        self.create_subscription(WrenchStamped, "/franka_state_controller/F_ext", self.on_wrench, 1)
        self.create_service(StartCooperativeLifting, "/start_cooperative_lifting", self.start)
        self.create_service(StopCooperativeLifting, "/stop_cooperative_lifting", self.stop)
        self.get_logger().info("node ready: lifting")

    def start(self, request, response):
        """f_n_min = force, f_n_max = f_n_min + 5, start; say it starts, with the force."""
        # TODO: self.f_n_min = ...; self.running = ...
        response.message = f"Cooperative lifting starts with {request.force:g} N"
        return response

    def stop(self, request, response):
        # TODO
        response.message = "Cooperative lifting stopped, f_n_min reset to 0 N"
        return response

    def on_state(self, msg):
        self.rotation = np.array(msg.O_T_EE).reshape(4, 4).T[:3, :3]  # column-major 4x4

    def on_wrench(self, msg):
        if self.rotation is None:
            return
        w = msg.wrench
        wrench = np.array([w.force.x, w.force.y, w.force.z, w.torque.x, w.torque.y, w.torque.z])
        t = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
        p = {name: self.get_parameter(name).value for name in self._parameters}
        if self.filtered is None or self.stamp is None or t <= self.stamp:
            self.filtered = wrench
        else:  # first-order low-pass against the sensor noise
            dt = t - self.stamp
            a = dt / (1.0 / (2.0 * math.pi * p["filter_hz"]) + dt)
            self.filtered = self.filtered + a * (wrench - self.filtered)
        self.stamp = t
        twist_ee = lifting_law(self.filtered, self.f_n_min, p) if self.running else np.zeros(6)
        v, omega = self.rotation @ twist_ee[:3], self.rotation @ twist_ee[3:]
        out = Twist()
        out.linear.x, out.linear.y, out.linear.z = v.tolist()
        out.angular.x, out.angular.y, out.angular.z = omega.tolist()
        self.command.publish(out)


def main():
    rclpy.init()
    node = Lifting()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
    node.destroy_node()
    rclpy.try_shutdown()


if __name__ == "__main__":
    main()
