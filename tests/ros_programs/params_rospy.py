#!/usr/bin/env python
"""rospy's parameter server: global, relative and private names; set, get, has, delete, defaults."""

import rospy

rospy.init_node("param_talker")
rospy.set_param("/lab/gains", {"k_n": 0.005, "k_t": [0.1, 0.2]})
rospy.set_param("greeting", "hello")
rospy.set_param("~rate", 5)
print("gains:", rospy.get_param("/lab/gains"), flush=True)
print("private rate:", rospy.get_param("/param_talker/rate"), rospy.get_param("~rate"), flush=True)
print("has greeting:", rospy.has_param("/greeting"), flush=True)
rospy.delete_param("greeting")
print("has greeting after delete:", rospy.has_param("greeting"), flush=True)
print("default:", rospy.get_param("greeting", "none"), flush=True)
try:
    rospy.get_param("greeting")
except KeyError as e:
    print("KeyError:", e, flush=True)
print("declared by the lab:", rospy.get_param("/cooperative_lifting/f_n_band"), flush=True)
