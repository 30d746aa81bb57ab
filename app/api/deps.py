"""Typed dependencies of the routers: what a request may use of the running app."""

from typing import Annotated, Any

from fastapi import Depends
from starlette.requests import HTTPConnection

from app.ros.actions import ActionServer
from app.ros.params import ParameterServer
from app.worlds.port import LabPort


def get_lab(connection: HTTPConnection) -> LabPort[Any]:
    return connection.app.state.lab


def get_params(connection: HTTPConnection) -> ParameterServer:
    return connection.app.state.lab.params


def get_actions(connection: HTTPConnection) -> ActionServer:
    return connection.app.state.actions


LabDep = Annotated[LabPort[Any], Depends(get_lab)]
ParamsDep = Annotated[ParameterServer, Depends(get_params)]
ActionsDep = Annotated[ActionServer, Depends(get_actions)]
