"""The services exercises graded over the lab's HTTP API: one item per handout service, with points
(`hri-lab grade-services`, app/cli/grade_services.py, is its command line; tests/exercises/ the same
items as one test each).

The lab is started with `hri-lab serve --exercises` and the student's node (from `hri-lab
template services`) provides the services; without `--exercises` the lab's own answers are
graded (the reference: full marks). Every case's numbers are drawn from the seed, so a course's
private seed gives cases students never saw and the same seed gives the same report.

The expected answers are computed here, independently of the lab's code: the planar arm's
torques from a finite-difference Jacobian of its forward kinematics, the Panda's tau = J(q)^T F
with this process's own pinocchio model at the q the lab reports on /joint_states (read before
and after each call: the robot must not move in between), and the least-squares wrench with
numpy. The report is the controller grader's (app/grading/report.py), in its formats.
"""

from __future__ import annotations

import math
import re
import string
from collections.abc import Callable
from dataclasses import dataclass

import httpx
import numpy as np
import pinocchio as pin

from sim.controllers.interface import LiftingParams
from sim.robot.assets import panda_urdf

from app.grading.report import Item, Report

SECTION = "services"
INT64_MAX = 2**63 - 1
TORQUE_TOLERANCE = 1e-4  # Nm (and N, Nm for the wrench), plus the same share of the value's size
STILL = 1e-9  # rad: the robot did not move between reading q and the call's answer


class Wrong(Exception):
    """A case the student's service answered wrongly (the item's detail)."""


@dataclass
class Answer:
    status: int
    body: dict

    @property
    def ok(self) -> bool:
        return self.status == 200


class LabClient:
    """The lab's HTTP API as the grader uses it: service calls and the topics' latest messages."""

    def __init__(self, url: str, token: str | None = None, timeout: float = 10.0):
        headers = {"Authorization": f"Bearer {token}"} if token else {}
        self.http = httpx.Client(base_url=url.rstrip("/"), headers=headers, timeout=timeout)

    def close(self) -> None:
        self.http.close()

    def call(self, service: str, request: dict | None = None) -> Answer:
        response = self.http.post(f"/services/{service.lstrip('/')}", json=request or {})
        try:
            body = response.json()
        except ValueError:
            body = {"detail": response.text}
        return Answer(response.status_code, body if isinstance(body, dict) else {"value": body})

    def answer(self, service: str, request: dict | None = None) -> dict:
        """A successful call's response, or Wrong with what the lab said instead."""
        answer = self.call(service, request)
        if not answer.ok:
            raise Wrong(f"{_short(request)} -> HTTP {answer.status}: {answer.body.get('detail', answer.body)}")
        return answer.body

    def topic(self, name: str) -> dict:
        return self.http.get(f"/topics/{name.lstrip('/')}").json()

    def joint_positions(self) -> np.ndarray:
        """q (rad) of the 7 arm joints as the lab reports it (/joint_states)."""
        return np.array(self.topic("joint_states")["position"], dtype=float)


def _short(request: dict | None) -> str:
    text = str(request or {})
    return text if len(text) <= 120 else text[:117] + "..."


def _close(got, expected, what: str, request: dict) -> None:
    got, expected = np.asarray(got, dtype=float), np.asarray(expected, dtype=float)
    if got.shape != expected.shape:
        raise Wrong(f"{_short(request)}: {what} has {got.size} values, expected {expected.size}")
    error = np.max(np.abs(got - expected))
    if not error <= TORQUE_TOLERANCE * (1.0 + np.max(np.abs(expected))):
        raise Wrong(
            f"{_short(request)}: {what} = {np.round(got, 4).tolist()}, expected "
            f"{np.round(expected, 4).tolist()} (off by {error:.3g})"
        )


# --- the independent answers -------------------------------------------------------------------
def planar_hand(q: np.ndarray) -> np.ndarray:
    """Forward kinematics of the 3-link planar arm (links of 1 m): hand [x, y, phi] (m, m, rad)."""
    theta = np.cumsum(q)
    return np.array([np.cos(theta).sum(), np.sin(theta).sum(), theta[-1]])


def planar_expected(q: np.ndarray, force: np.ndarray) -> np.ndarray:
    """tau = J(q)^T [fx, fy, mz] with J by central differences of planar_hand (Nm)."""
    step = 1e-6
    jacobian = np.column_stack(
        [(planar_hand(q + step * e) - planar_hand(q - step * e)) / (2 * step) for e in np.eye(3)]
    )
    return jacobian.T @ np.append(force, 0.0)[:3]


class PandaJacobian:
    """The flange (panda_link8) Jacobian in the base frame, built here with pinocchio from
    example-robot-data's panda.urdf (not the lab's model): twist_base = J(q) qdot, J 6x7."""

    def __init__(self):
        self.model = pin.buildModelFromUrdf(str(panda_urdf()))
        self.data = self.model.createData()
        self.frame = self.model.getFrameId("panda_link8")

    def __call__(self, q_arm: np.ndarray) -> np.ndarray:
        q = pin.neutral(self.model)
        q[:7] = q_arm  # the two finger joints come after the arm's and do not move the flange
        return pin.computeFrameJacobian(self.model, self.data, q, self.frame, pin.LOCAL_WORLD_ALIGNED)[:, :7]


# --- the items -----------------------------------------------------------------------------------
@dataclass
class Exercise:
    service: str
    points: float
    check: Callable[[Grading], None]  # raises Wrong at the first wrong case
    what: str


class Grading:
    """One grading run: the lab, the seed's random cases, the Panda model (made once)."""

    def __init__(self, lab: LabClient, seed: int):
        self.lab = lab
        self.rng = np.random.default_rng(
            [seed, 2]
        )  # the services' cases (the controller grader draws from [seed, 0|1])
        self._jacobian: PandaJacobian | None = None

    def jacobian(self, q: np.ndarray) -> np.ndarray:
        if self._jacobian is None:
            self._jacobian = PandaJacobian()
        return self._jacobian(q)

    def integers(self, low: int, high: int, n: int) -> list[int]:
        return [int(v) for v in self.rng.integers(low, high, size=n, endpoint=True)]

    def at_rest(self, service: str, request: dict) -> tuple[dict, np.ndarray]:
        """The answer and the robot's q while it was answered (unchanged before and after)."""
        for _ in range(5):
            q_before = self.lab.joint_positions()
            body = self.lab.answer(service, request)
            if np.max(np.abs(self.lab.joint_positions() - q_before)) <= STILL:
                return body, q_before
        raise Wrong("the robot kept moving during the calls (is cooperative lifting running? stop it first)")


def check_add_two_ints(g: Grading) -> None:
    a, b = g.integers(-(10**6), 10**6, 2)
    big = g.integers(0, 2**40, 1)[0]
    for request in ({"a": a, "b": b}, {"a": -a, "b": b}, {"a": 2**62 + big, "b": 2**62 - 1 - big}):  # exact int64
        got = g.lab.answer("add_two_ints", request)["sum"]
        if got != request["a"] + request["b"]:
            raise Wrong(f"{request}: sum = {got}, expected {request['a'] + request['b']}")


def check_divide_ints(g: Grading) -> None:
    a, b = g.integers(-(10**4), 10**4, 2)
    b = b or 7
    for request in ({"a": a, "b": b}, {"a": b, "b": a or 3}):
        body = g.lab.answer("divide_ints", request)
        expected = request["a"] / request["b"]
        if (
            not math.isclose(body["result"], expected, rel_tol=1e-12, abs_tol=1e-12)
            or body["message"] != "Division ok."
        ):
            raise Wrong(f"{request}: {body}, expected result {expected!r} and 'Division ok.'")
    body = g.lab.answer("divide_ints", {"a": a, "b": 0})
    if body["message"] != "Division by zero!":
        raise Wrong(f"{{'a': {a}, 'b': 0}}: message {body['message']!r}, expected 'Division by zero!'")


def check_multiply_three(g: Grading) -> None:
    a, b, c = g.integers(-2000, 2000, 3)
    got = g.lab.answer("multiply_three", {"a": a, "b": b, "c": c})["product"]
    if got != a * b * c:
        raise Wrong(f"a={a}, b={b}, c={c}: product = {got}, expected {a * b * c}")
    request = {"a": 2**40 + a, "b": 2**20, "c": 2**10}  # 2^70: outside int64
    answer = g.lab.call("multiply_three", request)
    if answer.ok:
        raise Wrong(f"{request}: answered {answer.body}, but a * b * c does not fit in int64 (fail the call)")


def check_echo(g: Grading) -> None:
    letters = string.ascii_letters + string.digits + " àèìòù-_!?"
    for n in (1, 12, 0):
        text = "".join(g.rng.choice(list(letters), size=n)) + ("ünï" if n == 12 else "")
        got = g.lab.answer("echo", {"in": text})["out"]
        if got != text:
            raise Wrong(f"in = {text!r}: out = {got!r}")


def check_login(g: Grading) -> None:
    name = "student" + str(g.integers(1, 999, 1)[0])
    wrong = g.integers(43, 10**6, 1)[0]
    for request, success in (
        ({"username": name, "magic_number": 42}, True),
        ({"username": name, "magic_number": wrong}, False),
        ({"username": "", "magic_number": 42}, False),
    ):
        body = g.lab.answer("login", request)
        if body["success"] is not success:
            raise Wrong(f"{request}: success = {body['success']}, expected {success}")


def check_planar_torques(g: Grading) -> None:
    for n in (2, 3, 2):
        q = np.round(g.rng.uniform(-math.pi, math.pi, 3), 3)
        force = np.round(g.rng.uniform(-20.0, 20.0, n), 2)
        request = {"q": q.tolist(), "force": force.tolist()}
        _close(g.lab.answer("planar_torques", request)["torques"], planar_expected(q, force), "torques", request)


def _wrench(g: Grading) -> np.ndarray:
    """A flange wrench [f (N), m (Nm)], base frame."""
    return np.round(np.concatenate((g.rng.uniform(-30.0, 30.0, 3), g.rng.uniform(-3.0, 3.0, 3))), 3)


def check_compute_torques(g: Grading) -> None:
    for _ in range(3):
        request = {"force": _wrench(g).tolist()}
        body, q = g.at_rest("compute_torques", request)
        _close(body["torques"], g.jacobian(q).T @ np.array(request["force"]), "tau (Nm)", request)


def check_compute_wrench(g: Grading) -> None:
    q = g.lab.joint_positions()
    wrench_base = _wrench(g)
    cases = [g.jacobian(q).T @ wrench_base, np.round(g.rng.uniform(-10.0, 10.0, 7), 3)]  # J^T F exactly; any tau
    for torques in cases:
        request = {"torques": torques.tolist()}
        body, q = g.at_rest("compute_wrench", request)
        expected, *_ = np.linalg.lstsq(g.jacobian(q).T, torques, rcond=None)  # argmin |J^T F - tau|
        _close(body["force"], expected, "F (N, Nm)", request)


_NUMBER = re.compile(r"[-+]?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?")


def _states(message: str, value: float) -> bool:
    return any(math.isclose(float(n), value, abs_tol=1e-6) for n in _NUMBER.findall(message))


def check_start(g: Grading) -> None:
    """The band is judged from the lab's state (f_n_min = force, f_n_max = force + f_n_band); the message
    must only state the force (the handout asks for one like "Cooperative lifting starts with 11.5 N")."""
    force = float(g.integers(16, 30, 1)[0]) / 2  # 8.0 .. 15.0 N in halves
    message = g.lab.answer("start_cooperative_lifting", {"force": force})["message"]
    state = g.lab.topic("lifting_state")
    f_n_max = force + LiftingParams().f_n_band
    if not (state["started"] and math.isclose(state["f_n_min"], force) and math.isclose(state["f_n_max"], f_n_max)):
        raise Wrong(
            f"force = {force}: the lab's /lifting_state shows started={state['started']}, "
            f"f_n_min={state['f_n_min']}, f_n_max={state['f_n_max']} (expected {force:g} and {f_n_max:g} N)"
        )
    if not _states(message, force):
        raise Wrong(f"force = {force}: message {message!r} does not state the force {force:g} N")


_STOPPED = re.compile(r"\bstop(ped|s)?\b", re.IGNORECASE)  # "stopped", "stops", "Stop"


def check_stop(g: Grading) -> None:
    """Stopped is judged from the lab's state (not started, f_n_min 0); the message must only say
    that lifting stopped (the handout's: "Cooperative Lifting was stopped! The force limit was set
    back to ..."): no number is asked of it."""
    message = g.lab.answer("stop_cooperative_lifting")["message"]
    state = g.lab.topic("lifting_state")
    if state["started"] or state["f_n_min"] != 0.0:
        raise Wrong(
            f"the lab's /lifting_state shows started={state['started']}, f_n_min={state['f_n_min']} after the stop"
        )
    if not _STOPPED.search(message):
        raise Wrong(f"message {message!r} does not say that lifting stopped")


EXERCISES = (  # in this order: the robot at rest for the torques, lifting last
    Exercise("/add_two_ints", 1, check_add_two_ints, "sum of two int64 (exact near 2^63)"),
    Exercise("/divide_ints", 1, check_divide_ints, "a / b, and 'Division by zero!'"),
    Exercise("/multiply_three", 1, check_multiply_three, "product; a product outside int64 fails"),
    Exercise("/echo", 1, check_echo, "out = in (unicode, empty)"),
    Exercise("/login", 1, check_login, "magic number 42, empty user name refused"),
    Exercise("/planar_torques", 2, check_planar_torques, "tau = J(q)^T F of the planar arm (Exercise 1)"),
    Exercise("/compute_torques", 3, check_compute_torques, "tau = J(q)^T F of the Panda at the lab's q (Exercise 8)"),
    Exercise("/compute_wrench", 2, check_compute_wrench, "least-squares F with J^T F = tau (Exercise 2)"),
    Exercise(
        "/start_cooperative_lifting", 2, check_start, "f_n_min = force, f_n_max = force + f_n_band (Exercises 11-14)"
    ),
    Exercise("/stop_cooperative_lifting", 1, check_stop, "f_n_min = 0, stopped (Exercises 11-14)"),
)


def grade_exercise(g: Grading, exercise: Exercise) -> Item:
    """One item: full points when every case is right, else 0 with the first wrong case."""
    name = f"{exercise.service}: {exercise.what}"
    try:
        exercise.check(g)
    except Wrong as wrong:
        return Item(SECTION, name, 0.0, exercise.points, str(wrong))
    except (KeyError, TypeError) as exc:  # a response without a field the .srv has: the lab checks, but be safe
        return Item(SECTION, name, 0.0, exercise.points, f"malformed answer: {type(exc).__name__}: {exc}")
    return Item(SECTION, name, exercise.points, exercise.points)


def grade_services(
    url: str, seed: int, token: str | None = None, progress: Callable[[Item], None] = lambda item: None
) -> Report:
    """Every exercise service of the lab at `url`, in order; the lab is reset before and after
    (robot at rest, lifting stopped). Raises httpx.HTTPError when the lab cannot be reached."""
    report = Report(subject=url, kind="services", seed=seed, full_points=sum(e.points for e in EXERCISES))
    lab = LabClient(url, token)
    try:
        reset = lab.call("reset_simulation")
        if not reset.ok:
            report.error = f"the lab refused /reset_simulation (HTTP {reset.status}: {reset.body.get('detail')})"
            return report
        grading = Grading(lab, seed)
        for exercise in EXERCISES:
            report.items.append(grade_exercise(grading, exercise))
            progress(report.items[-1])
        lab.call("reset_simulation")  # whatever the student's stop did, lifting ends with the grade
    finally:
        lab.close()
    return report
