#!/usr/bin/env python
"""services_rospy.py — the handout's service servers as your own rospy node.

    hri-lab template services > services_rospy.py
    hri-lab serve --exercises           # the lab with these services left to you
    hri-lab run services_rospy.py       # like rosrun: rospy works against the lab
    hri-lab service call /divide_ints '{a: 7, b: 2}'      # now answered by this node
    hri-lab grade-services              # grades what your node answers

Each handler gets the request and returns the response. rospy's return rules: the response
(`DivideIntsResponse(result, message)`), a dict of its fields, a tuple or list of its fields in
order, or, for a one-field response, the field's value. A list field is the exception: a bare list
is read as the list of the fields, so return `PlanarTorquesResponse(torques=tau.tolist())` (or
`{"torques": tau.tolist()}`), never `tau.tolist()` alone. Raise rospy.ServiceException("reason")
for a failed call. `hri-lab service show /divide_ints` prints a service's .srv. Units: N, Nm, rad.

Unfilled, every handler answers a well-formed wrong value and `hri-lab grade-services` gives
1/15 (add_two_ints, the done example). "Graded:" in each docstring is the rule its item checks
with cases drawn from the grade's seed (docs/students.md, "The services exercises").
"""

import numpy as np
import rospy
from hri_lab.msg import FrankaState
from hri_lab.srv import (
    AddTwoInts,
    AddTwoIntsResponse,
    ComputeTorques,
    ComputeTorquesResponse,
    ComputeWrench,
    ComputeWrenchResponse,
    DivideInts,
    Echo,
    Login,
    MultiplyThree,
    PlanarTorques,
    PlanarTorquesResponse,
    StartCooperativeLifting,
    StopCooperativeLifting,
)

INT64_MIN, INT64_MAX = -(2**63), 2**63 - 1
robot = {"O_Jac_EE": None}  # the latest franka_states Jacobian (42 numbers, 6x7 column-major)


def add_two_ints(req):
    """int64 a, int64 b --- int64 sum. (Done: the example.)
    Graded: the exact sum, also near 2^63."""
    return AddTwoIntsResponse(req.a + req.b)


def divide_ints(req):
    """int64 a, int64 b --- float64 result, string message.
    Graded: result = a / b with the message "Division ok."; for b = 0 the message "Division by zero!"."""
    return 0.0, ""  # TODO


def multiply_three(req):
    """int64 a, b, c --- int64 product.
    Graded: the exact product; a product outside int64 is a failed call (raise rospy.ServiceException)."""
    return 0  # TODO (raise rospy.ServiceException("...") when it does not fit in int64)


def echo(req):
    """string in --- string out (`in` is a Python keyword: the field is req.in_).
    Graded: out = in, for unicode text and the empty string."""
    return ""  # TODO


def login(req):
    """string username, int64 magic_number --- bool success, string message.
    Graded: success true for a non-empty user name with magic number 42 (message "Welcome, NAME!"),
    false for another number or an empty name (message "Login failed: ...")."""
    return False, "Login failed: TODO"


def planar_torques(req):
    """float64[3] q, float64[] force ([fx, fy] or [fx, fy, mz]) --- float64[] torques.
    Graded: tau = J(q)^T F of the 3-link planar arm (links of 1 m), 3 values, within 1e-4."""
    return PlanarTorquesResponse(torques=[0.0, 0.0, 0.0])  # TODO (a bare list would be read as the fields)


def compute_torques(req):
    """float64[6] force at the flange, base frame --- float64[] torques.
    Graded: tau = J(q)^T F (7 values, within 1e-4) at the robot's q, for three wrenches."""
    if robot["O_Jac_EE"] is None:
        raise rospy.ServiceException("no robot state received yet")
    jacobian = np.array(robot["O_Jac_EE"]).reshape(7, 6).T
    return ComputeTorquesResponse(torques=[0.0] * 7)  # TODO with jacobian


def compute_wrench(req):
    """float64[7] torques --- float64[] force, string message.
    Graded: the least-squares F (6 values, within 1e-4) with J^T F = tau, for a tau that J^T F makes
    and one that none does; the message is free (e.g. the residual)."""
    return ComputeWrenchResponse(force=[0.0] * 6, message="")  # TODO


def start_cooperative_lifting(req):
    """float64 force --- string message. When this answers, the lab applies the band
    f_n_min = force, f_n_max = force + 5 and starts.
    Graded: the lab's /lifting_state shows the band and started, and the message states the force
    (e.g. "Cooperative Lifting started with 11.5 N")."""
    return "TODO"


def stop_cooperative_lifting(req):
    """--- string message. When this answers, the lab stops lifting and sets f_n_min = 0.
    Graded: the lab's /lifting_state shows stopped with f_n_min 0, and the message says it stopped
    (e.g. "Cooperative Lifting was stopped! The force limit was set back to 0 N")."""
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
