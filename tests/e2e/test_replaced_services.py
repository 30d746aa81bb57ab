"""A program that serves one of the lab's own services (app/rosbridge/capabilities/advertise_service.py):
its answers replace the lab's while it runs, and the lab warns — the program's own log (what
`hri-lab run` prints), /rosout (the page's console, `GET /log`) — naming the way to leave the
handout's services to students' nodes (`--exercises`). An exercise a lab leaves to nodes, or a name
the lab does not declare, is no replacement: no warning."""

import roslibpy

from app.rosbridge.rosapi import LAB_NODE
from tests.e2e.serving import served_lab
from tests.http_client import http
from tests.ros_running import PROGRAMS, Program
from tests.waiting import wait_for

lab = served_lab()  # the lab with its own answers to the handout's services

WARNING = "/add_two_ints is one of the lab's own services"


def log_lines(lab) -> list[dict]:
    return http.get(f"{lab.url}/log").json()


def test_a_rospy_program_replacing_add_two_ints_is_warned_in_its_log_and_on_rosout(lab):
    program = Program(lab.url, "run", str(PROGRAMS / "add_two_ints_server_rospy.py"))
    try:
        line = program.wait_for_line(WARNING)
        assert line.startswith("[WARNING] lab: advertise_service:")
        assert "hri-lab serve --exercises" in line
        program.wait_for_line("Ready to add two ints")
        wait_for(lambda: http.get(f"{lab.url}/services/add_two_ints").json()["node"] != LAB_NODE, timeout=30)
        warned = [e for e in log_lines(lab) if WARNING in e["msg"]]
        assert [(e["level"], e["node"]) for e in warned] == [("WARN", "service")]
        assert http.post(f"{lab.url}/services/add_two_ints", json={"a": 20, "b": 22}).json() == {"sum": 42}
    finally:
        program.interrupt(timeout=30)


def test_a_roslibpy_node_is_warned_too_and_a_name_of_its_own_is_not(lab, ros):
    before = len([e for e in log_lines(lab) if "is one of the lab's own services" in e["msg"]])
    own = roslibpy.Service(ros, "/my_own_echo", "std_srvs/Trigger")
    own.advertise(lambda request, response: True)
    echo = roslibpy.Service(ros, "/echo", "hri_lab/Echo")
    echo.advertise(lambda request, response: response.update(out=request["in"].upper()) or True)
    try:
        wait_for(lambda: http.get(f"{lab.url}/services/echo").json()["node"] != LAB_NODE, timeout=30)
        assert http.post(f"{lab.url}/services/echo", json={"in": "up"}).json() == {"out": "UP"}
        warned = [e["msg"] for e in log_lines(lab) if "is one of the lab's own services" in e["msg"]]
        assert len(warned) == before + 1
        assert warned[-1].startswith("/echo is one of the lab's own services")
    finally:
        echo.unadvertise()
        own.unadvertise()
    wait_for(lambda: http.get(f"{lab.url}/services/echo").json()["node"] == LAB_NODE, timeout=30)  # the lab's again
