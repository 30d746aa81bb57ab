"""/actions: send goals, follow their feedback (long-poll or WebSocket) and cancel them
(ros2 action list / send_goal), for every action of the server: the lab's, and those nodes
provide over rosbridge (app/ros/node_actions.py)."""

import asyncio
from typing import Any

from fastapi import APIRouter, Body, HTTPException, Query, WebSocket, WebSocketDisconnect
from fastapi.responses import JSONResponse
from pydantic import ValidationError

from app.api.deps import ActionsDep
from app.api.topics import client_gone
from app.api.typed_routes import with_body
from app.ros.actions import TERMINAL, Action, ActionServer, GoalHandle, GoalStatus
from app.ros.messages import INT64_MAX, RosMessage
from app.ros.names import absolute


def router(actions: list[Action]) -> APIRouter:
    r = APIRouter(tags=["actions"])

    def goal_of(server: ActionServer, name: str, goal_id: str) -> GoalHandle:
        handle = server.goal(name, goal_id)
        if handle is None:
            raise HTTPException(404, f"no goal {goal_id} of action {absolute(name)}")
        return handle

    @r.get("/actions", summary="Actions with their types (ros2 action list -t): the lab's and the nodes'")
    def list_actions(server: ActionsDep) -> list[dict]:
        return [{"name": a.name, "type": a.type} for a in list(server.actions.values())]

    for action in actions:
        r.add_api_route(
            f"/actions{action.name}/goals",
            with_body(
                action.goal,
                lambda goal, server, a=action: _accept(server, a, goal),
                "send_goal" + action.name.replace("/", "_"),
                server=ActionsDep,
            ),
            methods=["POST"],
            status_code=202,
            summary=f"send a goal to {action.name} ({action.type})",
            description=f"{action.description}\n\n```\n{action.definition}\n```",
        )

    @r.post(
        "/actions/{name}/goals",
        status_code=202,
        summary="Send a goal to an action a node provides",
        description="The lab's actions have typed routes of their own (above); this one serves the actions "
        "nodes advertise at run time. The goal is checked against the action's type when the lab "
        "knows it (422 naming the field).",
    )
    def send_node_goal(name: str, server: ActionsDep, body: Any = Body(None)) -> JSONResponse:
        action = server.get(name)
        if action is None:
            return JSONResponse({"detail": f"action '{absolute(name)}' does not exist"}, status_code=404)
        try:
            goal = action.goal.model_validate(body if body is not None else {})
        except ValidationError as exc:  # FastAPI's shape: a list naming each field
            errors = [{"type": e["type"], "loc": ["body", *e["loc"]], "msg": e["msg"]} for e in exc.errors()]
            return JSONResponse({"detail": errors}, status_code=422)
        return _accept(server, action, goal)

    @r.get("/actions/{name}", summary="Type and .action definition of an action")
    def action_info(name: str, server: ActionsDep) -> dict:
        action = server.get(name)
        if action is None:
            raise HTTPException(404, f"action '{absolute(name)}' does not exist")
        return {
            "name": action.name,
            "type": action.type,
            "definition": action.definition,
            "description": action.description,
            "goal_schema": action.goal.model_json_schema(by_alias=True),
        }

    @r.get(
        "/actions/{name}/goals/{goal_id}",
        summary="Status, feedback and result of a goal (long-poll)",
        description="`wait` > 0: answer once there is feedback beyond the `after`-th, the goal ends, or "
        "`wait` s pass; a waiting request holds no thread.",
    )
    async def goal_status(
        name: str,
        goal_id: str,
        server: ActionsDep,
        after: int = Query(0, ge=0, le=INT64_MAX),
        wait: float = Query(0.0, ge=0.0, le=30.0),
    ) -> dict:
        handle = goal_of(server, name, goal_id)
        if wait > 0:
            await handle.updated(after, wait)
        return handle.view(after)

    @r.post("/actions/{name}/goals/{goal_id}/cancel", summary="Cancel a goal")
    def cancel(name: str, goal_id: str, server: ActionsDep) -> dict:
        handle = goal_of(server, name, goal_id)
        server.cancel(handle)
        return handle.view(len(handle.feedbacks))

    @r.websocket("/actions/{name}/goals/{goal_id}/stream")
    async def stream(websocket: WebSocket, name: str, goal_id: str, server: ActionsDep) -> None:
        handle = server.goal(name, goal_id)
        if handle is None:
            await websocket.close(code=1008, reason="no such goal")
            return
        await websocket.accept()
        sent = 0
        gone = asyncio.ensure_future(client_gone(websocket))
        try:
            while not gone.done():
                update = asyncio.ensure_future(handle.updated(sent, 5.0))
                await asyncio.wait([gone, update], return_when=asyncio.FIRST_COMPLETED)
                update.cancel()
                view = handle.view(sent)  # one snapshot: its feedback and its status (a goal that ends
                for fb in view["feedback"]:  # after it is taken ends at the next turn, with its result)
                    await websocket.send_json({"feedback": fb})
                sent = view["feedback_count"]
                if GoalStatus(view["status"]) in TERMINAL:
                    await websocket.send_json(
                        {"status": view["status"], "result": view["result"], "message": view["message"]}
                    )
                    await websocket.close()
                    return
        except (WebSocketDisconnect, RuntimeError):
            return
        finally:
            gone.cancel()

    return r


def _accept(server: ActionServer, action: Action, goal: RosMessage) -> JSONResponse:
    handle = server.send_goal(action, goal)
    return JSONResponse(handle.view(), status_code=202 if handle.status != GoalStatus.REJECTED else 409)
