"""The lab's services (docs/design.md, "Services"), one declaration each: request, response, handler."""

from typing import Annotated

import numpy as np
from pydantic import Field

from sim import camera
from sim.controllers.builtin import BUILTIN
from sim.controllers.interface import ControllerFault
from sim.robot import planar_arm

from app.lab import commands as cmd
from app.lab.params import F_N_MIN_RANGE
from app.lab.recorder import LiveRecorder
from app.recording import services as recording
from app.ros.messages import (
    INT64_MAX,
    INT64_MIN,
    Bool,
    Empty,
    Float64,
    Float64Array,
    Int32,
    Int64,
    RosMessage,
    RosType,
    String,
)
from app.ros.services import Service, ServiceFailure, ServiceRegistry


class Trigger(RosMessage):
    success: Bool
    message: String


class Message(RosMessage):
    message: String


# --- cooperative lifting --------------------------------------------------------------------
class StartRequest(RosMessage):
    force: Annotated[
        float, Field(ge=F_N_MIN_RANGE[0], le=F_N_MIN_RANGE[1], allow_inf_nan=False, examples=[10.0]), RosType("float64")
    ]
    controller: Annotated[
        str,
        Field(pattern="^(|" + "|".join(BUILTIN) + ")$"),
        RosType("string", "'' keeps the current one; " + " or ".join(BUILTIN)),
    ] = ""


def start(lab, request: StartRequest) -> Message:
    """Select the controller (when given) and start, in one step of the simulation."""
    message = _lifting_handler(lab, cmd.start_lifting, request.force, request.controller)
    lab.info("cooperative_lifting", message)
    return Message(message=message)


def _lifting_handler(lab, fn, *args) -> str:
    """start/stop run the controller's own handler when it has one: its failure is the call's."""
    try:
        return str(lab.call(fn, *args))
    except ControllerFault as fault:
        raise ServiceFailure(str(fault)) from None


def stop(lab, request: Empty) -> Message:
    message = _lifting_handler(lab, cmd.stop_lifting)
    lab.info("cooperative_lifting", message)
    return Message(message=message)


# --- exercises ------------------------------------------------------------------------------
class WrenchRequest(RosMessage):
    force: Annotated[Float64Array, Field(min_length=6, max_length=6)]


class Torques(RosMessage):
    torques: Float64Array


def _finite(values: np.ndarray, what: str) -> list[float]:
    """The values as a list, or a service failure when huge inputs overflowed float64."""
    if not np.all(np.isfinite(values)):
        raise ServiceFailure(f"{what} overflows float64 (inputs too large)")
    return values.tolist()


def compute_torques(lab, request: WrenchRequest) -> Torques:
    """tau = J(q)^T F at the robot's current q; F at the flange, base frame."""
    q = lab.snapshot().q
    return Torques(torques=_finite(lab.model.torques_from_wrench(q, np.array(request.force)), "tau = J^T F"))


class TorquesRequest(RosMessage):
    torques: Annotated[Float64Array, Field(min_length=7, max_length=7)]


class WrenchResponse(RosMessage):
    force: Float64Array
    message: String


def compute_wrench(lab, request: TorquesRequest) -> WrenchResponse:
    """Least-squares F with J^T F = tau (Exercise 2)."""
    wrench, residual = lab.model.wrench_from_torques(lab.snapshot().q, np.array(request.torques))
    return WrenchResponse(
        force=_finite(wrench, "the least-squares wrench"),
        message=f"least-squares wrench; residual |J^T F - tau| = {residual:.3g} Nm",
    )


class PlanarRequest(RosMessage):
    q: Annotated[Float64Array, Field(min_length=3, max_length=3)]
    force: Annotated[Float64Array, Field(min_length=2, max_length=3)]


def planar_torques(lab, request: PlanarRequest) -> Torques:
    """3-DoF planar arm, links of 1 m: tau = J(q)^T [fx, fy(, mz)]."""
    return Torques(torques=_finite(planar_arm.torques(np.array(request.q), np.array(request.force)), "tau = J^T F"))


class TwoInts(RosMessage):
    a: Int64
    b: Int64


class Sum(RosMessage):
    sum: Int64


def _int64(value: int, what: str) -> int:
    if not INT64_MIN <= value <= INT64_MAX:
        raise ServiceFailure(f"{what} = {value} does not fit in int64")
    return value


def add_two_ints(lab, request: TwoInts) -> Sum:
    return Sum(sum=_int64(request.a + request.b, "a + b"))


class Quotient(RosMessage):
    result: Float64
    message: String


def divide_ints(lab, request: TwoInts) -> Quotient:
    if request.b == 0:
        return Quotient(result=0.0, message="Division by zero!")
    return Quotient(result=request.a / request.b, message="Division ok.")  # |a/b| <= 2^63: finite


class ThreeInts(RosMessage):
    a: Int64
    b: Int64
    c: Int64


class Product(RosMessage):
    product: Int64


def multiply_three(lab, request: ThreeInts) -> Product:
    return Product(product=_int64(request.a * request.b * request.c, "a * b * c"))


class EchoRequest(RosMessage):
    in_: String = Field(alias="in")


class EchoResponse(RosMessage):
    out: String


def echo(lab, request: EchoRequest) -> EchoResponse:
    return EchoResponse(out=request.in_)


class LoginRequest(RosMessage):
    username: String
    magic_number: Int64


MAGIC_NUMBER = 42


def login(lab, request: LoginRequest) -> Trigger:
    """The seed's login: any non-empty user name with the magic number 42."""
    if not request.username.strip():
        return Trigger(success=False, message="Login failed: empty username.")
    if request.magic_number != MAGIC_NUMBER:
        return Trigger(success=False, message=f"Login failed: wrong magic number for {request.username}.")
    return Trigger(success=True, message=f"Welcome, {request.username}!")


class TargetRequest(RosMessage):
    get: Bool


class Pixel(RosMessage):
    x: Int32
    y: Int32


def get_target_position(lab, request: TargetRequest) -> Pixel:
    if not request.get:
        lab.info("get_target_position", "get is false: no target position computed")
        return Pixel(x=0, y=0)
    try:
        s = lab.snapshot()
        x, y = camera.box_in_image(s.box_position, s.box_rotation, lab.call(cmd.scene_geometry)["box"])
    except ValueError:
        raise ServiceFailure("the box is behind the camera") from None
    return Pixel(x=x, y=y)


def error_recovery(lab, request: Empty) -> Trigger:
    error = lab.call(cmd.recover)
    if error is None:
        return Trigger(success=True, message="No error to recover from.")
    return Trigger(success=True, message=f"Recovered from: {error}")


def reset_simulation(lab, request: Empty) -> Trigger:
    lab.call(cmd.reset_world)
    return Trigger(
        success=True,
        message="Simulation reset: lifting stopped, robot at the start pose, box held in front of the plate.",
    )


SERVICES = ServiceRegistry(
    [
        Service(
            "/start_cooperative_lifting",
            "hri_lab/StartCooperativeLifting",
            StartRequest,
            Message,
            start,
            "Start cooperative lifting: f_n_min = force, f_n_max = force + f_n_band (a parameter); "
            "controller 'sp' or 'patch' selects the lifting controller first ('' keeps the current one).",
        ),
        Service(
            "/stop_cooperative_lifting",
            "hri_lab/StopCooperativeLifting",
            Empty,
            Message,
            stop,
            "Stop cooperative lifting: f_n_min = 0, the robot stops (zero twist).",
        ),
        Service(
            "/compute_torques",
            "hri_lab/ComputeTorques",
            WrenchRequest,
            Torques,
            compute_torques,
            "Joint torques tau = J(q)^T F of the Panda at its current q; F = [fx, fy, fz, mx, my, mz] at the flange, base frame.",
        ),
        Service(
            "/compute_wrench",
            "hri_lab/ComputeWrench",
            TorquesRequest,
            WrenchResponse,
            compute_wrench,
            "Least-squares flange wrench from 7 joint torques (Exercise 2).",
        ),
        Service(
            "/planar_torques",
            "hri_lab/PlanarTorques",
            PlanarRequest,
            Torques,
            planar_torques,
            "Torques of the 3-DoF planar arm (links of 1 m) for a hand force [fx, fy] or [fx, fy, mz] (Exercise 1).",
        ),
        Service("/add_two_ints", "hri_lab/AddTwoInts", TwoInts, Sum, add_two_ints, "sum = a + b"),
        Service("/divide_ints", "hri_lab/DivideInts", TwoInts, Quotient, divide_ints, "result = a / b"),
        Service("/multiply_three", "hri_lab/MultiplyThree", ThreeInts, Product, multiply_three, "product = a * b * c"),
        Service("/echo", "hri_lab/Echo", EchoRequest, EchoResponse, echo, "out = in"),
        Service(
            "/login", "hri_lab/Login", LoginRequest, Trigger, login, "Log in with a user name and the magic number."
        ),
        Service(
            "/get_target_position",
            "hri_lab/GetObjectPosition",
            TargetRequest,
            Pixel,
            get_target_position,
            "The box's centre in the image of the lab's 640x480 camera (/image_raw), as a detection finds it: the centre of its bounding rectangle (get=false: 0, 0).",
        ),
        Service(
            "/error_recovery",
            "std_srvs/Trigger",
            Empty,
            Trigger,
            error_recovery,
            "Clear the robot's reflex error (franka's error recovery).",
        ),
        Service(
            "/reset_simulation",
            "std_srvs/Trigger",
            Empty,
            Trigger,
            reset_simulation,
            "Reset the world: lifting stopped, robot at the start pose, box held by the person in front of the plate.",
        ),
        *recording.services(  # topics 100 Hz, /tf and /scene 25 Hz, until /stop_recording (app/lab/recorder.py)
            LiveRecorder,
            "the live lab to an MCAP file (like ros2 bag record): Foxglove opens it; hri-lab play replays it.",
            " (index, summary)",
        ),
    ]
)

# What a node's answer of these does to the lab (app/ros/node_services.py): the world's side of
# the service, which the lab's own handlers (start, stop) apply in the same step
NODE_EFFECTS = {
    "/start_cooperative_lifting": lambda lab, request: lab.call(cmd.lifting_effect, True, request.force),
    "/stop_cooperative_lifting": lambda lab, request: lab.call(cmd.lifting_effect, False),
}

# `hri-lab serve --exercises`: these stay declared but are left to the students' nodes
EXERCISES = (
    "/add_two_ints",
    "/divide_ints",
    "/multiply_three",
    "/echo",
    "/login",
    "/planar_torques",
    "/compute_torques",
    "/compute_wrench",
    "/start_cooperative_lifting",
    "/stop_cooperative_lifting",
    "/get_target_position",
)
