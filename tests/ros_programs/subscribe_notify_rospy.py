#!/usr/bin/env python
"""A publisher told of its peers (rospy.SubscribeListener), as rospy's tutorial writes one: it greets
each node that subscribes and notices when they leave."""

import rospy
from std_msgs.msg import String


class ChatterListener(rospy.SubscribeListener):
    def peer_subscribe(self, topic_name, topic_publish, peer_publish):
        print("a peer subscribed to topic [%s]" % topic_name, flush=True)
        peer_publish(String("greetings. welcome to topic " + topic_name))

    def peer_unsubscribe(self, topic_name, num_peers):
        print("a peer unsubscribed from topic [%s], %d left" % (topic_name, num_peers), flush=True)


if __name__ == "__main__":
    rospy.init_node("talker_callback")
    rospy.Publisher("chatter_peers", String, ChatterListener(), queue_size=10)
    print("publishing", flush=True)
    rospy.spin()
