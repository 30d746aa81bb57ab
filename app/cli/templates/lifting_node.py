"""lifting_node.py — the lifting application as a node (Exercise 16): F_ext in, velocity commands out.

    hri-lab template node > lifting_node.py
    make run                       # the live lab (http://127.0.0.1:8000/)
    python lifting_node.py         # this node drives the robot through the lab's rosbridge
    hri-lab service call /start_cooperative_lifting '{force: 10}'    # served by this node

The node subscribes to /franka_state_controller/F_ext (geometry_msgs/WrenchStamped: the wrench the
ROBOT applies to the box, at the flange, flange frame; pressing gives f_n = force.z > 0) and to the
flange pose (franka_states' O_T_EE), and answers every F_ext message with a geometry_msgs/Twist on
/cartesian_velocity_controller/command: the flange twist in the BASE frame (m/s, rad/s).
As on the real Panda: a command not renewed within 100 ms stops the robot ("communication
constraints violation"; /error_recovery clears it), a command beyond the limits (1.7 m/s,
2.5 rad/s) trips a reflex, and changes are smoothed like libfranka's limit_rate (1 m/s^2).
As it is, it runs and commands zero twist. Needs roslibpy and numpy.
"""

import argparse
import math
import os
import time

import numpy as np
import roslibpy

PARAMS = {}  # @lab-defaults
lifting = {"running": False, "f_n_min": 0.0}  # set by the start/stop services below


def start_cooperative_lifting(request, response):
    """f_n_min = force, f_n_max = f_n_min + 5, start (the lab shows the band; the person waits for it)."""
    # TODO: lifting["f_n_min"] = ...; lifting["running"] = ...
    response["message"] = f"Cooperative Lifting started with f_n_min = {request['force']:g} N."
    return True


def stop_cooperative_lifting(request, response):
    """f_n_min = 0, stop (zero twist)."""
    # TODO: lifting["f_n_min"] = ...; lifting["running"] = ...
    response["message"] = "Cooperative Lifting was stopped! Force limit f_n_min reset to 0 N."
    return True


def lifting_law(wrench_ee, f_n_min, p):
    """The SP method: F_ext (6, flange frame, filtered) -> twist_ee (6, flange frame).
    n = [0, 0, 1] is the plate normal; its centre p_c = [0, 0, p["plate_offset"]]."""
    f, m = wrench_ee[:3], wrench_ee[3:]
    # TODO step 1: f_n = n . f; f_t = f - f_n n; m_c = m - p_c x f
    # TODO step 2: band [f_n_min, f_n_min + f_n_band]: below -> +n (press), above -> -n, inside -> 0 (gain k_n)
    # TODO step 3: |f_t| > alpha mu f_n -> v_t = -k_t e_t, e_t = f_t - alpha mu f_n f_t/|f_t|; and press harder
    # TODO step 4: comply with the moment: w = -k_w m_c (deadband moment_deadband), in contact only
    # TODO step 5a: saturate |v| <= v_max, |w| <= w_max
    return np.zeros(6)


class LiftingNode:
    """F_ext -> low-pass -> lifting_law -> rotate to the base frame -> publish."""

    def __init__(self, ros, law=lifting_law, period_ms=5):
        self.law = law
        self.rotation = None  # flange -> base, from franka_states' O_T_EE
        self.filtered, self.stamp = None, None
        self.command = roslibpy.Topic(ros, "/cartesian_velocity_controller/command", "geometry_msgs/Twist")
        self.command.advertise()
        roslibpy.Topic(
            ros, "/franka_state_controller/franka_states", "hri_lab/FrankaState", throttle_rate=20
        ).subscribe(self.on_state)  # the pose changes slowly: 50 Hz
        roslibpy.Topic(
            ros, "/franka_state_controller/F_ext", "geometry_msgs/WrenchStamped", throttle_rate=period_ms
        ).subscribe(self.on_wrench)

    def on_state(self, message):
        self.rotation = np.array(message["O_T_EE"]).reshape(4, 4).T[:3, :3]  # column-major 4x4

    def on_wrench(self, message):
        if self.rotation is None:
            return
        w = message["wrench"]
        wrench = np.array(
            [w["force"]["x"], w["force"]["y"], w["force"]["z"], w["torque"]["x"], w["torque"]["y"], w["torque"]["z"]]
        )
        stamp = message["header"]["stamp"]
        t = stamp["sec"] + stamp["nanosec"] * 1e-9
        # first-order low-pass against the sensor noise: w_f += a (w - w_f), a = dt / (1/(2 pi f_c) + dt)
        if self.filtered is None or self.stamp is None or t <= self.stamp:
            self.filtered = wrench
        else:
            dt = t - self.stamp
            a = dt / (1.0 / (2.0 * math.pi * PARAMS["filter_hz"]) + dt)
            self.filtered = self.filtered + a * (wrench - self.filtered)
        self.stamp = t
        twist_ee = self.law(self.filtered, lifting["f_n_min"], PARAMS) if lifting["running"] else np.zeros(6)
        twist_base = np.concatenate((self.rotation @ twist_ee[:3], self.rotation @ twist_ee[3:]))
        v, w = twist_base[:3].tolist(), twist_base[3:].tolist()
        self.command.publish(roslibpy.Message({"linear": dict(zip("xyz", v)), "angular": dict(zip("xyz", w))}))


def main(law=lifting_law, start=start_cooperative_lifting, stop=stop_cooperative_lifting):
    parser = argparse.ArgumentParser(description="The lifting application as a node.")
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=8000)
    args = parser.parse_args()
    token = os.environ.get("HRI_LAB_TOKEN")  # a lab served with a token needs it for changes
    ros = roslibpy.Ros(args.host, args.port, headers={"Authorization": f"Bearer {token}"} if token else None)
    ros.run()
    LiftingNode(ros, law)
    roslibpy.Service(ros, "/start_cooperative_lifting", "hri_lab/StartCooperativeLifting").advertise(start)
    roslibpy.Service(ros, "/stop_cooperative_lifting", "hri_lab/StopCooperativeLifting").advertise(stop)
    print(f"node ready: lifting through ws://{args.host}:{args.port}/", flush=True)
    try:
        while ros.is_connected:
            time.sleep(0.2)
    except KeyboardInterrupt:
        pass
    ros.terminate()


if __name__ == "__main__":
    main()
