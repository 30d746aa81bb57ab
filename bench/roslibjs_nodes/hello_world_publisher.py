#!/usr/bin/env python
"""`rostopic pub /listener std_msgs/String "Hello, World"` as a rospy program (roslibjs's test setup,
test/examples/setup_examples.launch, starts that command): the message latched, as rostopic pub
latches it, for every subscriber that comes."""

import rospy
from std_msgs.msg import String

if __name__ == "__main__":
    rospy.init_node("hello_world_publisher")
    pub = rospy.Publisher("/listener", String, queue_size=1, latch=True)
    pub.publish(String(data="Hello, World"))
    rospy.spin()
