#!/usr/bin/env python
"""services_rospy.py — the handout's service servers as your own rospy node.

    hri-lab template services > services_rospy.py
    hri-lab serve --exercises           # the lab with these services left to you
    hri-lab run services_rospy.py       # like rosrun: rospy works against the lab
    hri-lab service call /divide_ints '{a: 7, b: 2}'      # now answered by this node
    hri-lab grade-services              # grades what your node answers

Each handler gets the request and returns the response (rospy also takes a tuple of its fields, or
the value of a one-field response); raise rospy.ServiceException("reason") for a failed call.
`hri-lab service show /divide_ints` prints a service's .srv. Units: N, Nm, rad.
"""

import numpy as np
import rospy
from hri_lab.msg import FrankaState
from hri_lab.srv import (
    AddTwoInts,
    AddTwoIntsResponse,
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

INT64_MIN, INT64_MAX = -(2**63), 2**63 - 1
robot = {"O_Jac_EE": None}  # the latest franka_states Jacobian (42 numbers, 6x7 column-major)


def add_two_ints(req):
    """int64 a, int64 b --- int64 sum. (Done: the example.)"""
    return AddTwoIntsResponse(req.a + req.b)


def divide_ints(req):
    """int64 a, int64 b --- float64 result, string message: a / b and "Division ok.";
    for b = 0: 0.0 and "Division by zero!"."""
    return 0.0, ""  # TODO


def multiply_three(req):
    """int64 a, b, c --- int64 product; a product outside int64 is a failed call."""
    return 0  # TODO (raise rospy.ServiceException("...") when it does not fit in int64)


def echo(req):
    """string in --- string out = in (`in` is a Python keyword: the field is req.in_)."""
    return ""  # TODO


def login(req):
    """string username, int64 magic_number --- bool success, string message: success for a
    non-empty user name with 42 ("Welcome, NAME!"), else "Login failed: ..."."""
    return False, "Login failed: TODO"


def planar_torques(req):
    """float64[3] q, float64[] force ([fx, fy] or [fx, fy, mz]) --- float64[] torques: tau = J(q)^T F
    of the 3-link planar arm, links of 1 m."""
    return [0.0, 0.0, 0.0]  # TODO


def compute_torques(req):
    """float64[6] force at the flange, base frame --- float64[] torques (7): tau = J(q)^T F."""
    if robot["O_Jac_EE"] is None:
        raise rospy.ServiceException("no robot state received yet")
    jacobian = np.array(robot["O_Jac_EE"]).reshape(7, 6).T
    return [0.0] * 7  # TODO with jacobian


def compute_wrench(req):
    """float64[7] torques --- float64[] force (6): the least-squares F with J^T F = tau."""
    return [0.0] * 6, ""  # TODO (force, message)


def start_cooperative_lifting(req):
    """float64 force --- string message: f_n_min = force, f_n_max = f_n_min + 5; say it starts, with the force."""
    return "TODO"


def stop_cooperative_lifting(req):
    """--- string message: f_n_min = 0; say it stopped."""
    return "TODO"


def on_state(msg):
    robot["O_Jac_EE"] = msg.O_Jac_EE


if __name__ == "__main__":
    rospy.init_node("services_node")
    rospy.Subscriber("/franka_state_controller/franka_states", FrankaState, on_state, queue_size=1)
    for name, kind, handler in (
        ("add_two_ints", AddTwoInts, add_two_ints),
        ("divide_ints", DivideInts, divide_ints),
        ("multiply_three", MultiplyThree, multiply_three),
        ("echo", Echo, echo),
        ("login", Login, login),
        ("planar_torques", PlanarTorques, planar_torques),
        ("compute_torques", ComputeTorques, compute_torques),
        ("compute_wrench", ComputeWrench, compute_wrench),
        ("start_cooperative_lifting", StartCooperativeLifting, start_cooperative_lifting),
        ("stop_cooperative_lifting", StopCooperativeLifting, stop_cooperative_lifting),
    ):
        rospy.Service(name, kind, handler)
    rospy.loginfo("node ready: the handout's services")
    rospy.spin()
