#!/usr/bin/env python
"""rospy_tutorials' param talker in a namespace: a global, a relative (the launch group's), a
private and a searched parameter, and the names the node resolves."""

import rospy
from std_msgs.msg import String


def param_talker():
    rospy.init_node("param_talker")
    utterance = rospy.get_param("utterance")  # /foo/utterance: the node's namespace
    global_example = rospy.get_param("/global_example")
    topic_name = rospy.get_param("~topic_name")  # /foo/param_talker/topic_name
    found = rospy.search_param("searched")  # set above the node's namespace
    print("name %s namespace %s" % (rospy.get_name(), rospy.get_namespace()), flush=True)
    print("utterance: %s" % utterance, flush=True)
    print("global_example: %s" % global_example, flush=True)
    print("topic_name: %s" % topic_name, flush=True)
    print("search_param: %s = %s" % (found, rospy.get_param(found)), flush=True)
    print("resolve_name: %s %s" % (rospy.resolve_name(topic_name), rospy.resolve_name("~private")), flush=True)
    pub = rospy.Publisher(topic_name, String, queue_size=10)
    while not rospy.is_shutdown():
        pub.publish(utterance)
        rospy.sleep(0.2)


if __name__ == "__main__":
    try:
        param_talker()
    except rospy.ROSInterruptException:
        pass
