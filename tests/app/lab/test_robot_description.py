"""The lab's `/robot_description` parameter is the Panda's URDF text, as ROS has it (rosapi over the
lab's rosbridge endpoint, HTTP), and read-only with the reason (app/lab/robot_description.py,
app/ros/param_tree.py)."""

import json

from sim.robot.assets import panda_urdf

PANDA_URDF = panda_urdf().read_text(encoding="utf-8")


def rosapi(ws, service: str, **args) -> dict:
    ws.send_text(json.dumps({"op": "call_service", "id": service, "service": f"/rosapi/{service}", "args": args}))
    while True:
        answer = json.loads(ws.receive_text())
        if answer.get("op") == "service_response" and answer.get("id") == service:
            return answer


def test_robot_description_is_the_pandas_urdf_over_rosbridge(client):
    with client.websocket_connect("/") as ws:
        answer = rosapi(ws, "get_param", name="/robot_description")
        assert answer["result"]
        assert json.loads(answer["values"]["value"]) == PANDA_URDF
        assert rosapi(ws, "has_param", name="robot_description")["values"] == {"exists": True}
        assert "/robot_description" in rosapi(ws, "get_param_names")["values"]["names"]
        assert rosapi(ws, "search_param", name="robot_description")["values"]["global_name"] == "/robot_description"


def test_robot_description_is_read_only_with_the_reason(client):
    with client.websocket_connect("/") as ws:
        for service, args in (
            ("set_param", {"name": "/robot_description", "value": json.dumps("<robot name='mine'/>")}),
            ("delete_param", {"name": "/robot_description"}),
            ("set_param", {"name": "/", "value": json.dumps({"robot_description": 1})}),
        ):
            answer = rosapi(ws, service, **args)
            if service == "set_param" and args["name"] == "/":  # the root set keeps the read-only name
                assert answer["result"]
            else:
                assert not answer["result"]
                assert "/robot_description is read-only (the lab's robot, the Panda's URDF" in answer["values"]
        assert json.loads(rosapi(ws, "get_param", name="/robot_description")["values"]["value"]) == PANDA_URDF


def test_robot_description_over_http(client):
    response = client.get("/robot/description")
    assert response.status_code == 200
    assert response.headers["content-type"].startswith("application/xml")
    assert response.text == PANDA_URDF
    assert client.get("/robot").json()["name"] == "panda"
