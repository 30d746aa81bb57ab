"""services_node.py — the handout's service servers as your own node, served by the lab (roslibpy).

    hri-lab template services > services_node.py
    hri-lab serve --exercises        # the lab with these services left to you (with `make run` yours replace the lab's)
    python services_node.py          # connects to the lab's rosbridge at ws://127.0.0.1:8000/
    hri-lab service call /divide_ints '{a: 7, b: 2}'      # now answered by this node

Each handler gets the request (a dict) and fills the response (a dict); it returns True, or False
for a failed call (then fill response["error"] with the reason). The lab checks every answer
against the service's .srv (`hri-lab service show /divide_ints`). When this node stops, its services
go with it. Units: N, Nm, rad. Needs roslibpy (pip install roslibpy).

Unfilled, every handler answers a well-formed wrong value and `hri-lab grade-services` gives
1/15 (add_two_ints, the done example). "Graded:" in each docstring is the rule its item checks
with cases drawn from the grade's seed (docs/students.md, "The services exercises").
"""

import argparse
import os
import time

import numpy as np
import roslibpy

INT64_MIN, INT64_MAX = -(2**63), 2**63 - 1
robot = {"O_Jac_EE": None}  # the latest /franka_state_controller/franka_states fields you need


def add_two_ints(request, response):
    """AddTwoInts: int64 a, int64 b --- int64 sum. (Done: the example.)
    Graded: the exact sum, also near 2^63."""
    response["sum"] = request["a"] + request["b"]
    return True


def divide_ints(request, response):
    """DivideInts: int64 a, int64 b --- float64 result, string message.
    result = a / b and "Division ok."; for b = 0: result 0.0 and "Division by zero!".
    Graded: result = a / b with the message "Division ok."; for b = 0 the message "Division by
    zero!"."""
    # TODO
    response["result"] = 0.0
    response["message"] = ""
    return True


def multiply_three(request, response):
    """MultiplyThree: int64 a, b, c --- int64 product. A product outside int64 is a failure.
    Graded: the exact product; a product outside int64 is a failed call."""
    # TODO (return False with response["error"] = "..." when it does not fit in int64)
    response["product"] = 0
    return True


def echo(request, response):
    """Echo: string in --- string out = in.
    Graded: out = in, for unicode text and the empty string."""
    # TODO
    response["out"] = ""
    return True


def login(request, response):
    """Login: string username, int64 magic_number --- bool success, string message.
    Success for a non-empty user name with the magic number 42: "Welcome, NAME!"; else "Login failed: ...".
    Graded: success for a non-empty user name with 42 ("Welcome, NAME!"), failure for another number
    or an empty name."""
    # TODO
    response["success"] = False
    response["message"] = "Login failed: TODO"
    return True


def planar_torques(request, response):
    """PlanarTorques (Exercise 1): float64[3] q, float64[] force ([fx, fy] or [fx, fy, mz]) --- float64[] torques.
    The 3-link planar arm, links of 1 m: tau = J(q)^T F, theta_i = q_1 + ... + q_i,
    J = [[-sum_{i>=j} sin(theta_i)], [sum_{i>=j} cos(theta_i)], [1]] (columns j = 1..3).
    Graded: tau = J(q)^T F of the planar arm, 3 values within 1e-4, for [fx, fy] and [fx, fy, mz]."""
    # TODO
    response["torques"] = [0.0, 0.0, 0.0]
    return True


def compute_torques(request, response):
    """ComputeTorques (Exercise 8): float64[6] force = [fx, fy, fz, mx, my, mz] at the flange, base frame
    --- float64[] torques (7): tau = J(q)^T F at the robot's current q.
    J: robot["O_Jac_EE"], 42 numbers, the 6x7 flange Jacobian column-major (libfranka's zeroJacobian):
    J = np.array(robot["O_Jac_EE"]).reshape(7, 6).T
    Graded: tau = J(q)^T F, 7 values within 1e-4, at the robot's q, for three wrenches."""
    if robot["O_Jac_EE"] is None:
        response["error"] = "no robot state received yet"
        return False
    # TODO
    response["torques"] = [0.0] * 7
    return True


def compute_wrench(request, response):
    """ComputeWrench (Exercise 2): float64[7] torques --- float64[] force, string message.
    The least-squares F with J^T F = tau (np.linalg.lstsq); the message may report the residual.
    Graded: the least-squares F, 6 values within 1e-4, for a tau that J^T F makes and one none does."""
    # TODO
    response["force"] = [0.0] * 6
    response["message"] = "least-squares wrench"
    return True


def start_cooperative_lifting(request, response):
    """StartCooperativeLifting: float64 force, string controller --- string message.
    f_n_min = force, f_n_max = f_n_min + 5: "Cooperative Lifting started with f_n_min = 10 N, f_n_max = 15 N."
    (The lab then shows that band and the person waits for it.)
    Graded: the lab applies the band when this answers (its /lifting_state must show started,
    f_n_min = force, f_n_max = force + 5), and the message states the force ("Cooperative
    Lifting started with 11.5 N")."""
    # TODO
    response["message"] = "TODO"
    return True


def stop_cooperative_lifting(request, response):
    """StopCooperativeLifting: --- string message. f_n_min = 0:
    "Cooperative Lifting was stopped! Force limit f_n_min reset to 0 N."
    Graded: the lab stops when this answers (its /lifting_state must show stopped, f_n_min 0), and
    the message says it stopped ("Cooperative Lifting was stopped! The force limit was set back
    to 0 N")."""
    # TODO
    response["message"] = "TODO"
    return True


SERVERS = {  # name: (type, handler)
    "/add_two_ints": ("hri_lab/AddTwoInts", add_two_ints),
    "/divide_ints": ("hri_lab/DivideInts", divide_ints),
    "/multiply_three": ("hri_lab/MultiplyThree", multiply_three),
    "/echo": ("hri_lab/Echo", echo),
    "/login": ("hri_lab/Login", login),
    "/planar_torques": ("hri_lab/PlanarTorques", planar_torques),
    "/compute_torques": ("hri_lab/ComputeTorques", compute_torques),
    "/compute_wrench": ("hri_lab/ComputeWrench", compute_wrench),
    "/start_cooperative_lifting": ("hri_lab/StartCooperativeLifting", start_cooperative_lifting),
    "/stop_cooperative_lifting": ("hri_lab/StopCooperativeLifting", stop_cooperative_lifting),
}


# --- the node (no need to change below) ------------------------------------------------------
def guarded(handler):
    """A handler that raises answers a failure with the error, instead of no answer at all."""

    def serve(request, response):
        try:
            return bool(handler(request, response))
        except Exception as exc:  # noqa: BLE001 - any error of a handler becomes its call's failure
            response.clear()
            response["error"] = f"{type(exc).__name__}: {exc}"
            return False

    return serve


def main(servers=SERVERS):
    parser = argparse.ArgumentParser(description="The handout's service servers as a node.")
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=8000)
    args = parser.parse_args()
    token = os.environ.get("HRI_LAB_TOKEN")  # a lab served with a token needs it for changes
    ros = roslibpy.Ros(args.host, args.port, headers={"Authorization": f"Bearer {token}"} if token else None)
    ros.run()
    state = roslibpy.Topic(ros, "/franka_state_controller/franka_states", "hri_lab/FrankaState", throttle_rate=20)
    state.subscribe(lambda message: robot.update(O_Jac_EE=message["O_Jac_EE"]))
    for name, (type_name, handler) in servers.items():
        roslibpy.Service(ros, name, type_name).advertise(guarded(handler))
    print(f"node ready: serving {', '.join(servers)} on ws://{args.host}:{args.port}/", flush=True)
    try:
        while ros.is_connected:
            time.sleep(0.2)
    except KeyboardInterrupt:
        pass
    ros.terminate()


if __name__ == "__main__":
    main()
