"""rclpy's QoS events between programs (the lab's `endpoints` op told back, as DDS discovery tells
a participant the remote readers and writers: app/rosbridge/capabilities/endpoints.py,
rosclient/site/rclpy/_endpoints.py): a BEST_EFFORT talker and RELIABLE listeners, each its own
`hri-lab run` program, are told incompatible QoS on both sides (their callbacks, rclpy's default
warning without one); the listeners hear nothing of the incompatible talker while a compatible
talker's messages arrive; the compatible talker counts in the listener's liveliness and matched
events while it runs and leaves them when it ends."""

import subprocess

from tests.e2e.serving import served_lab
from tests.ros_running import run

lab = served_lab()

RELIABILITY = "last_policy_kind: rmw_qos_policy_kind_t.RMW_QOS_POLICY_RELIABILITY"


def test_incompatible_programs_are_told_on_both_sides_and_hear_nothing_of_each_other(lab):
    listener = run(lab.url, "qos_listener_rclpy.py", "listener")
    quiet = run(lab.url, "qos_listener_rclpy.py", "quiet_listener", "--default")
    programs = [listener, quiet]
    try:
        listener.wait_for_line("listening")
        quiet.wait_for_line("listening")
        fast = run(lab.url, "qos_talker_rclpy.py", "fast_talker", "best_effort")
        programs.append(fast)
        listener.wait_for_line(f"Requested incompatible qos - total 1 delta 1 {RELIABILITY}")
        fast.wait_for_line(f"Offered incompatible qos - total 2 delta 1 {RELIABILITY}")  # one for each listener
        assert quiet.wait_for_line("offering incompatible QoS").endswith(
            "[quiet_listener]: New publisher discovered on topic 'qos_chatter', offering incompatible QoS. No messages "
            "will be received from it. Last incompatible policy: RELIABILITY"
        )
        good = run(lab.url, "qos_talker_rclpy.py", "good_talker", "reliable", "--default")
        programs.append(good)
        listener.wait_for_line("liveliness alive=1 change=1 not_alive=0")  # the compatible talker only
        listener.wait_for_line("matched current=1 change=1")
        fast.wait_for_line("published 10")  # ten messages since both listeners subscribed
        heard = int(listener.wait_for_line("heard: good_talker").split()[-1])
        for program in (listener, quiet):  # well after the fast talker's 10th message reached the lab
            program.wait_for_line(f"heard: good_talker {heard + 10}")
        assert good.interrupt() == 0, good.output
        listener.wait_for_line("liveliness alive=0 change=-1 not_alive=0")
        listener.wait_for_line("matched current=0 change=-1")
    finally:
        for program in programs:  # each one stopped, even when one before it hung in its Ctrl+C
            try:
                program.interrupt()
            except subprocess.TimeoutExpired:
                pass  # killed by interrupt() itself
    for program in (listener, quiet):
        assert not [line for line in program.lines if "heard: fast_talker" in line], program.output
    assert "matched" not in fast.output  # no listener matched it
    assert "incompatible" not in good.output
