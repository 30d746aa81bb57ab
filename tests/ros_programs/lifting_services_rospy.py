#!/usr/bin/env python
"""The cooperative-lifting start/stop servers (rospy): f_n_max = f_n_min + 5."""

import rospy
from hri_lab.srv import StartCooperativeLifting, StartCooperativeLiftingResponse, StopCooperativeLifting

band = {"f_n_min": 0.0, "f_n_max": 0.0}


def handle_start(req):
    band["f_n_min"] = req.force
    band["f_n_max"] = band["f_n_min"] + 5
    rospy.loginfo("band %.1f .. %.1f N", band["f_n_min"], band["f_n_max"])
    return StartCooperativeLiftingResponse("Cooperative lifting starts with %.1f N" % req.force)


def handle_stop(req):
    band["f_n_min"] = 0.0
    return "Cooperative lifting stopped, f_n_min reset to 0 N"  # a single-field response by its value


if __name__ == "__main__":
    rospy.init_node("cooperative_lifting_server")
    rospy.Service("/start_cooperative_lifting", StartCooperativeLifting, handle_start)
    rospy.Service("/stop_cooperative_lifting", StopCooperativeLifting, handle_stop)
    rospy.loginfo("lifting services ready")
    rospy.spin()
    print("spin returned", flush=True)
