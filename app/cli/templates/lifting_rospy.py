#!/usr/bin/env python
"""lifting_rospy.py — the lifting application of Exercise 16 as a rospy node: it reads F_ext, runs
your SP law and commands the robot with a Twist (the lab's command watchdog stops the robot when
the commands stop), and it provides the start/stop services.

    hri-lab template node > lifting_rospy.py
    hri-lab run lifting_rospy.py
    hri-lab service call /start_cooperative_lifting '{force: 10}'

As it is, it runs and commands zero twist. Units: N, Nm, m/s, rad/s.
"""

import math

import numpy as np
import rospy
from geometry_msgs.msg import Twist, WrenchStamped
from hri_lab.msg import FrankaState
from hri_lab.srv import StartCooperativeLifting, StopCooperativeLifting

PARAMS = {}  # @lab-defaults
lifting = {"running": False, "f_n_min": 0.0}
state = {"rotation": None, "filtered": None, "stamp": None}


def start(req):
    """f_n_min = force, f_n_max = f_n_min + 5, start; say it starts, with the force."""
    # TODO: lifting["f_n_min"] = ...; lifting["running"] = ...
    return "Cooperative lifting starts with %g N" % req.force


def stop(req):
    """f_n_min = 0, stop (zero twist)."""
    # TODO
    return "Cooperative lifting stopped, f_n_min reset to 0 N"


def lifting_law(wrench_ee, f_n_min, p):
    """The SP method: F_ext (6, flange frame, filtered) -> twist_ee (6, flange frame)."""
    # TODO the steps of the handout: band on f_n, slip on f_t, comply with m_c, saturate
    return np.zeros(6)


def on_state(msg):
    state["rotation"] = np.array(msg.O_T_EE).reshape(4, 4).T[:3, :3]  # column-major 4x4


def on_wrench(msg, command):
    if state["rotation"] is None:
        return
    w = msg.wrench
    wrench = np.array([w.force.x, w.force.y, w.force.z, w.torque.x, w.torque.y, w.torque.z])
    t = msg.header.stamp.to_sec()
    if state["filtered"] is None or state["stamp"] is None or t <= state["stamp"]:
        state["filtered"] = wrench
    else:  # first-order low-pass against the sensor noise
        dt = t - state["stamp"]
        a = dt / (1.0 / (2.0 * math.pi * PARAMS["filter_hz"]) + dt)
        state["filtered"] = state["filtered"] + a * (wrench - state["filtered"])
    state["stamp"] = t
    twist_ee = lifting_law(state["filtered"], lifting["f_n_min"], PARAMS) if lifting["running"] else np.zeros(6)
    rotation = state["rotation"]
    v, omega = rotation @ twist_ee[:3], rotation @ twist_ee[3:]
    out = Twist()
    out.linear.x, out.linear.y, out.linear.z = v.tolist()
    out.angular.x, out.angular.y, out.angular.z = omega.tolist()
    command.publish(out)


if __name__ == "__main__":
    rospy.init_node("cooperative_lifting")
    command = rospy.Publisher("/cartesian_velocity_controller/command", Twist, queue_size=1)
    rospy.Subscriber("/franka_state_controller/franka_states", FrankaState, on_state, queue_size=1)
    rospy.Subscriber("/franka_state_controller/F_ext", WrenchStamped, on_wrench, command, queue_size=1)
    rospy.Service("/start_cooperative_lifting", StartCooperativeLifting, start)
    rospy.Service("/stop_cooperative_lifting", StopCooperativeLifting, stop)
    rospy.loginfo("node ready: lifting")
    rospy.spin()
