"""Exercise 16 in the live lab with a rospy program under `hri-lab run`: the lifting node
(tests/ros_programs/lifting_node_rospy.py) carries the calm participant's box, driving the robot
only through rosbridge (F_ext in, Twist commands out). As tests/e2e/test_lifting_node.py (the roslibpy
node), the command period is raised to 5 s: the test machine is shared (tests/e2e/lifting.py)."""

from tests.e2e.lifting import carry_the_box, slow_commands
from tests.e2e.serving import running_server
from tests.ros_running import run


def test_the_rospy_lifting_node_carries_the_box():
    with running_server("--view", "none") as lab:
        slow_commands(lab.url)
        node = run(lab.url, "lifting_node_rospy.py")
        try:
            node.wait_for_line("lifting node ready")
            # carried and held between plate and palm to the end (carry_the_box). How far the box slid
            # in the palm on the way depends on how promptly the program's process gets a core, as for
            # the roslibpy node (tests/e2e/test_lifting_node.py: 3.5-9 cm on a loaded 2-core machine;
            # CI saw 8.7 cm here), so it is reported, not asserted
            slip = carry_the_box(lab.url, "f_n_max = 15 N", timeout_s=180)
            print(f"the box slid {slip * 100:.1f} cm in the palm")
        finally:
            node.interrupt()
