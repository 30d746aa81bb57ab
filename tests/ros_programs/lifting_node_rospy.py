#!/usr/bin/env python
"""The lifting node of Exercise 16 in rospy: F_ext (low-passed) through the SP law to a Twist on the
robot's command topic, with the start/stop services (f_n_max = f_n_min + 5). The F_ext callback only
filters each 1 kHz sample; a rospy.Timer runs the law on the newest at CONTROL_HZ, as the roslibpy
template's node does (throttle_rate 5 ms): Python running the law and a publish at 1 kHz needs most
of a core, which a shared machine does not give it, and a late command is an unstable one."""

import math

import numpy as np
import rospy
from geometry_msgs.msg import Twist, WrenchStamped
from hri_lab.msg import FrankaState
from hri_lab.srv import StartCooperativeLifting, StopCooperativeLifting

CONTROL_HZ = 200.0

P = {
    "f_n_band": 5.0,
    "mu": 0.5,
    "alpha": 0.8,
    "k_n": 0.005,
    "k_t": 0.1,
    "k_w": 1.0,
    "moment_deadband": 0.1,
    "f_contact": 1.0,
    "v_max": 0.5,
    "w_max": 1.0,
    "filter_hz": 10.0,
    "plate_offset": 0.02,
}


class Lifting:
    def __init__(self):
        self.running, self.f_n_min = False, 0.0
        self.rotation, self.filtered, self.stamp = None, None, None
        self.command = rospy.Publisher("/cartesian_velocity_controller/command", Twist, queue_size=1)
        rospy.Subscriber("/franka_state_controller/franka_states", FrankaState, self.on_state, queue_size=1)
        rospy.Subscriber("/franka_state_controller/F_ext", WrenchStamped, self.on_wrench, queue_size=1)
        rospy.Service("/start_cooperative_lifting", StartCooperativeLifting, self.start)
        rospy.Service("/stop_cooperative_lifting", StopCooperativeLifting, self.stop)
        rospy.Timer(rospy.Duration(1.0 / CONTROL_HZ), self.control)

    def start(self, req):
        self.f_n_min, self.running = req.force, True
        f_n_max = self.f_n_min + 5
        return "Cooperative lifting starts: f_n_min = %g N, f_n_max = %g N" % (self.f_n_min, f_n_max)

    def stop(self, req):
        self.f_n_min, self.running = 0.0, False
        return "Cooperative lifting stopped, f_n_min reset to 0 N"

    def on_state(self, msg):
        self.rotation = np.array(msg.O_T_EE).reshape(4, 4).T[:3, :3]

    def on_wrench(self, msg):
        f, m = msg.wrench.force, msg.wrench.torque
        wrench = np.array([f.x, f.y, f.z, m.x, m.y, m.z])
        t = msg.header.stamp.to_sec()
        if self.filtered is None or self.stamp is None or t <= self.stamp:
            self.filtered = wrench
        else:
            dt = t - self.stamp
            a = dt / (1.0 / (2.0 * math.pi * P["filter_hz"]) + dt)
            self.filtered = self.filtered + a * (wrench - self.filtered)
        self.stamp = t

    def control(self, event):
        filtered, rotation = self.filtered, self.rotation
        if filtered is None or rotation is None:
            return
        twist = sp_law(filtered, self.f_n_min) if self.running else np.zeros(6)
        v, w = rotation @ twist[:3], rotation @ twist[3:]
        out = Twist()
        out.linear.x, out.linear.y, out.linear.z = v.tolist()
        out.angular.x, out.angular.y, out.angular.z = w.tolist()
        self.command.publish(out)


def clip(x, limit):
    norm = np.linalg.norm(x)
    return x * (limit / norm) if norm > limit else x


def sp_law(wrench, f_n_min):
    """Keep the normal force in the band, press harder and slide back when the box slips, follow the moment."""
    fx, fy, f_n, mx, my, mz = wrench
    f_n_max = f_n_min + P["f_n_band"]
    d = P["plate_offset"]
    moment = np.array([mx + d * fy, my - d * fx, mz])
    touching = f_n >= P["f_contact"]
    if f_n < f_n_min:
        v_n = P["k_n"] * (f_n_min - f_n)
    elif f_n > f_n_max:
        v_n = -P["k_n"] * (f_n - f_n_max)
    else:
        v_n = 0.0
    v_t = np.zeros(2)
    f_t = math.hypot(fx, fy)
    allowed = P["alpha"] * P["mu"] * max(f_n, 0.0)
    if touching and f_t > allowed:
        v_t = -P["k_t"] * (1.0 - allowed / f_t) * np.array([fx, fy])
        if f_n < f_n_max:
            v_n = max(v_n, P["k_n"] * (f_n_max - f_n))
    w = np.zeros(3)
    size = np.linalg.norm(moment)
    if touching and size > P["moment_deadband"]:
        w = -P["k_w"] * (1.0 - P["moment_deadband"] / size) * moment
    return np.concatenate((clip(np.array([v_t[0], v_t[1], v_n]), P["v_max"]), clip(w, P["w_max"])))


if __name__ == "__main__":
    rospy.init_node("cooperative_lifting")
    Lifting()
    rospy.loginfo("lifting node ready")
    rospy.spin()
