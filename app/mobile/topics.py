"""The mobile world's topics as the server serves them: the snapshot's (sim/mobile/messages.py) and
the robot's URDF on /robot_description (std_msgs/String, latched as robot_state_publisher's); how
often each is sent at most (s), and which only when it changed."""

from __future__ import annotations

from sim.messages import Topic
from sim.mobile.messages import CMD_VEL
from sim.mobile.messages import TOPICS as MOBILE_TOPICS
from sim.mobile.urdf import burger_urdf

ROBOT_DESCRIPTION = "/robot_description"
COMMAND_TOPIC = CMD_VEL

TOPICS = [*MOBILE_TOPICS, Topic(ROBOT_DESCRIPTION, "std_msgs/String", lambda s: {"data": burger_urdf()})]
# at most this often to one subscriber (s): turtlebot3_node's odometry and joint states at 30 Hz
MIN_PERIOD_S = {
    "/scan": 0.05,
    "/odom": 1 / 30,
    "/joint_states": 1 / 30,
    "/tf": 1 / 30,
    "/tf_static": 0.1,
    ROBOT_DESCRIPTION: 1.0,
    "/clock": 0.01,
}
# sent only when the message changed: each scan once (5 Hz), the latched ones (transient local)
LATCHED = {"/scan", "/tf_static", ROBOT_DESCRIPTION}
