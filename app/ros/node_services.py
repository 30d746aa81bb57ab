"""Services provided by nodes: a rosbridge client advertises a service, the lab lists it with the
others (`GET /services`, `service list -t`, the page) and every caller — HTTP, the CLI, the
dashboard, another node — reaches it through the same registry entry, whose handler sends the
request to the node and waits for its `service_response`.

- The request is validated with the service type's model before it leaves (422 naming the
  field over HTTP); the node's answer is validated with the response model (502 naming the field
  when it is not one), so a caller only ever sees a well-formed response.
- A node that does not answer within `timeout` (NODE_SERVICE_TIMEOUT) fails the call with 504
  naming the service; a node that disconnects takes its services with it (calls in flight fail).
- A node may serve a name the lab declares (same type, .srv and route): its answers replace the
  lab's while it is connected, the lab's come back when it leaves. Exercise mode (`hri-lab serve
  --exercises`): the handout's exercise services stay declared but are left to the students:
  "not provided yet" (404) until a node advertises the name. A node's successful
  start/stop_cooperative_lifting also applies its effect to the lab (the band the person
  expects, the running flag), as the lab's own service does: the lab's `effects`
  (app/lab/services.py NODE_EFFECTS), handed in by whoever builds the registry.
"""

from __future__ import annotations

import asyncio
import itertools
import threading
from collections.abc import Callable, Mapping
from concurrent.futures import Future
from contextlib import contextmanager
from dataclasses import dataclass, replace
from typing import Any, Protocol

from pydantic import ConfigDict, ValidationError

from app.ros.interface_models import BadDefinition, own_text, service_models
from app.ros.messages import Bool, Empty, RosMessage, String, definition, validation_reason
from app.ros.services import NodeFailure, NodeTimeout, NotProvided, Service, ServiceFailure, ServiceRegistry

NODE_SERVICE_TIMEOUT = 2.0  # s a node has to answer a call


class OpenMessage(RosMessage):
    """A message of a type the lab does not know: any JSON object, passed through."""

    model_config = ConfigDict(strict=True, extra="allow")


class SetBoolRequest(RosMessage):
    data: Bool


class SetBoolResponse(RosMessage):
    success: Bool
    message: String


def service_types(registry: ServiceRegistry) -> dict[str, tuple[type[RosMessage], type[RosMessage]]]:
    """Service type -> (request, response) models: the lab's declared types and common std ones."""
    types = {s.type: (s.request, s.response) for s in registry}
    types.setdefault("std_srvs/Empty", (Empty, Empty))
    types["std_srvs/SetBool"] = (SetBoolRequest, SetBoolResponse)
    for alias in ("example_interfaces/AddTwoInts", "rospy_tutorials/AddTwoInts"):
        if "hri_lab/AddTwoInts" in types:  # the lifting lab's (the mobile world declares no services)
            types[alias] = types["hri_lab/AddTwoInts"]
    return types


def normalise_type(name: str) -> str:
    """`pkg/srv/Name` (ROS 2 spelling) -> `pkg/Name`."""
    parts = name.strip("/").split("/")
    return f"{parts[0]}/{parts[-1]}" if len(parts) == 3 and parts[1] in ("srv", "msg", "action") else name.strip("/")


class NodeClient(Protocol):
    """A node's connection, as the registries of node services and actions reach it (a rosbridge
    session, app/rosbridge/session.py): its name, its event loop and what sends it a message."""

    @property
    def name(self) -> str: ...

    @property
    def loop(self) -> asyncio.AbstractEventLoop | None: ...

    async def send(self, message: dict) -> None: ...


@dataclass
class Provider:
    session: NodeClient
    type: str


class NodeServices:
    def __init__(
        self,
        base: ServiceRegistry,
        lab: Any,
        exercises: tuple[str, ...] = (),
        timeout: float = NODE_SERVICE_TIMEOUT,
        effects: Mapping[str, Callable[[Any, RosMessage], None]] | None = None,
        caller: str = "",
    ) -> None:
        self.lab = lab
        self.caller = caller  # the lab's own node: the `callerid` of a call from HTTP, the CLI or the page
        self.effects = dict(effects or {})  # service name -> what a node's answer does to the lab
        self.timeout = timeout
        self.slots = {name for name in exercises if base.get(name) is not None}
        self.declared = {s.name for s in base}
        self.registry = ServiceRegistry([self._declared(s) for s in base])
        self._declarations = {s.name: s for s in self.registry}  # restored when a node stops serving one
        self.types = service_types(base)
        self.providers: dict[str, Provider] = {}
        self._pending: dict[str, tuple[Future, NodeClient]] = {}
        self._ids = itertools.count(1)
        self._lock = threading.Lock()

    # --- declarations -----------------------------------------------------------------------
    def _declared(self, service: Service) -> Service:
        """A declared service: a node's answer while one provides it, else the lab's (or, for an
        exercise, "not provided yet")."""
        own = None if service.name in self.slots else service.handler
        name = service.name

        def handler(lab, request: RosMessage) -> RosMessage:
            if own is None or name in self.providers:
                return self.call(name, request)
            return own(lab, request)

        note = " Left to the students: a node provides it." if own is None else ""
        return Service(
            name,
            service.type,
            service.request,
            service.response,
            self._logged(name, handler),
            service.description + note,
        )

    def _handler(self, name: str):
        def handler(lab, request: RosMessage) -> RosMessage:
            return self.call(name, request)

        return self._logged(name, handler)

    def _logged(self, name: str, handler):
        """The handler, its calls on /rosout: answered (DEBUG, who answered), failed (ERROR, why)."""

        def logged(lab, request: RosMessage) -> RosMessage:
            provider = self.providers.get(name)
            by = f"node {provider.session.name}" if provider is not None else "the lab"
            try:
                response = handler(lab, request)
            except Exception as exc:
                lab.rosout.log("service", f"call of {name} failed ({by}): {exc}", "ERROR")
                raise
            lab.rosout.log("service", f"{name} answered by {by}", "DEBUG")
            return response

        return logged

    def advertise(
        self,
        name: str,
        type_name: str,
        session: NodeClient,
        text: str | None = None,
        models: tuple[type[RosMessage], type[RosMessage]] | None = None,
    ) -> str | None:
        """A node provides `name`, typed by its carried .srv `text` when it sent one (else by the
        type's name; `models`, the text's, when the caller built them already: `models_of`); raises
        ServiceFailure with the reason it cannot. Returns a warning for the node, or None."""
        if text is not None and models is None:
            models = models_of(type_name, text)
        with self._lock:
            current = self.providers.get(name)
            if current is not None and current.session is not session:
                raise ServiceFailure(f"service {name} is already provided by node {current.session.name}")
            self.providers[name] = Provider(session, type_name)
            if name in self.declared:
                warning = self._serve_declared(name, type_name, models, text)
            else:
                warning = None
                self._serve_undeclared(name, type_name, models, text, session)
        if warning:
            self.lab.rosout.log("service", warning, "WARN")  # the console; a status for a node that asks for warnings
        return warning

    def _serve_undeclared(
        self, name: str, type_name: str, models: tuple | None, text: str | None, session: NodeClient
    ) -> None:
        """A name the lab does not declare: typed by the node's carried text, or by its type's name."""
        if models is not None:
            (request, response), note = models, ""
        else:
            request, response = self.types.get(normalise_type(type_name), (OpenMessage, OpenMessage))
            note = (
                ""
                if request is not OpenMessage
                else f"; type {type_name} is unknown to the lab: request and response are passed through as JSON objects"
            )
        self.registry.remove(name)
        self.registry.add(
            Service(
                name,
                type_name,
                request,
                response,
                self._handler(name),
                f"provided by node {session.name}{note}",
                text=own_text(text or ""),
            )
        )

    def _serve_declared(self, name: str, type_name: str, models: tuple | None, text: str | None) -> str | None:
        """A node serves a name the lab declares: the lab's type checks the requests (its typed
        route); the node's own text is shown while it provides the name when its fields are the
        declared ones, else a warning (on /rosout, and to the node) says the lab checks against its own."""
        declared = self._declarations[name]
        if models is None:
            return None
        same = all(
            _lines(definition(d)) == _lines(definition(m))
            for d, m in zip((declared.request, declared.response), models)
        )
        if not same:
            self.registry.put(declared)
            return (
                f"{name} is declared by the lab as {declared.type}; its requests and answers are checked "
                f"against that definition, not {type_name}'s:\n{declared.srv}"
            )
        self.registry.put(replace(declared, type=type_name, text=own_text(text or "")))
        return None

    def answers_itself(self, name: str) -> bool:
        """Whether the lab answers `name` itself now (declared, not left to the students, and no
        node provides it): a node advertising it replaces the lab's own service."""
        with self._lock:
            return name in self.declared and name not in self.slots and name not in self.providers

    def unadvertise(self, name: str, session: NodeClient) -> bool:
        with self._lock:
            provider = self.providers.get(name)
            if provider is None or provider.session is not session:
                return False
            del self.providers[name]
            if name in self.declared:
                self.registry.put(self._declarations[name])
            else:
                self.registry.remove(name)
            failed = [f for f, s in self._pending.values() if s is session]
        for future in failed:  # its calls in flight fail now, not after the timeout
            _fail(future, NodeFailure(f"node {session.name} withdrew service {name} before answering"))
        return True

    def drop(self, session: NodeClient) -> None:
        """A node disconnected: its services go with it."""
        for name in [n for n, p in list(self.providers.items()) if p.session is session]:
            self.unadvertise(name, session)

    def provided_by(self, name: str) -> Provider | None:
        return self.providers.get(name)

    def node_of(self, name: str) -> str | None:
        """The node (rosbridge client) that provides `name` now; None: nobody but the lab."""
        provider = self.providers.get(name)
        return provider.session.name if provider is not None else None

    def offered(self, name: str) -> bool:
        """Somebody answers `name` now: the lab, or a node (an exercise left to the nodes is not
        offered until one provides it, as a ROS service exists only while its server runs)."""
        return name not in self.slots or name in self.providers

    def goes_to_node(self, name: str) -> bool:
        """A call of `name` is a node's to answer (provided, or an exercise left to the nodes)."""
        return name in self.providers or name in self.slots

    # --- calls ------------------------------------------------------------------------------
    def _request(self, name: str) -> tuple[str, Future, Provider]:
        with self._lock:
            provider = self.providers.get(name)
            if provider is None:
                if name in self.slots:
                    raise NotProvided(f"service {name} is not provided yet: a node must advertise it")
                raise NotProvided(f"service {name} is not advertised")
            call_id = f"lab:{name}:{next(self._ids)}"
            future: Future = Future()
            self._pending[call_id] = (future, provider.session)
        return call_id, future, provider

    @contextmanager
    def _calling(self, name: str, request: RosMessage, header: dict[str, str] | None = None):
        """One call of the node's service, pending while the block runs: yields the provider, the
        call_service message to send it and the future of its answer; a wait beyond `timeout` (s)
        is a NodeTimeout naming the service. The message carries the caller's connection header
        (`connection_header`: its `callerid` and what it added, as a ROS 1 service client sends;
        the lab's own calls: the lab's node), which rosbridge clients ignore."""
        call_id, future, provider = self._request(name)
        message = {"op": "call_service", "id": call_id, "service": name, "args": request.model_dump(by_alias=True)}
        if header is None and self.caller:
            header = {"callerid": self.caller}
        if header is not None:
            message["connection_header"] = header
        try:
            yield provider, message, future
        except TimeoutError:  # concurrent.futures' and asyncio's are this one
            raise NodeTimeout(
                f"service {name}: node {provider.session.name} did not answer within {self.timeout:g} s"
            ) from None
        finally:
            with self._lock:
                self._pending.pop(call_id, None)

    def call(self, name: str, request: RosMessage) -> RosMessage:
        """Call the node's service from any thread (HTTP, CLI, dashboard, 3D view); blocks."""
        with self._calling(name, request) as (provider, message, future):
            try:
                asyncio.run_coroutine_threadsafe(provider.session.send(message), provider.session.loop)
                ok, values = future.result(timeout=self.timeout)
            except RuntimeError as exc:  # the node's connection is closing (its loop is gone)
                raise NodeFailure(f"service {name}: node {provider.session.name} is gone ({exc})") from None
        response = self._response(name, ok, values)
        self._effect(name, request)
        return response

    async def call_async(self, name: str, request: RosMessage, header: dict[str, str] | None = None) -> RosMessage:
        """The same from the server's event loop (a node calling another node's service: `header`,
        its connection header)."""
        by = "a node"
        try:
            with self._calling(name, request, header) as (provider, message, future):
                by = f"node {provider.session.name}"
                await provider.session.send(message)
                ok, values = await asyncio.wait_for(asyncio.wrap_future(future), self.timeout)
            response = self._response(name, ok, values)
        except Exception as exc:
            self.lab.rosout.log("service", f"call of {name} failed ({by}): {exc}", "ERROR")
            raise
        self.lab.rosout.log("service", f"{name} answered by {by}", "DEBUG")
        await asyncio.to_thread(self._effect, name, request)
        return response

    def answer(self, session: NodeClient, call_id: object, ok: bool, values: Any) -> bool:
        """A node's service_response; False when no call of this node waits for it."""
        if not isinstance(call_id, str):  # the lab's calls have string ids
            return False
        with self._lock:
            pending = self._pending.get(call_id)
            if pending is None or pending[1] is not session:
                return False
            del self._pending[call_id]
        pending[0].set_result((ok, values))
        return True

    def _response(self, name: str, ok: bool, values: Any) -> RosMessage:
        """The node's answer as the service's response. As rosbridge_suite's service_response does
        (what roslibpy's and roslibjs' servers were tested against), `result: false` with values
        that are a response still delivers them: the call succeeds with those values. Values that
        are no response make a failed call: with `result: false`, the values are its reason."""
        service = self.registry.get(name)
        if service is None:  # the node withdrew it while answering
            raise NodeFailure(f"service {name} is no longer provided")
        try:
            return service.response.model_validate(values if values is not None else {})
        except ValidationError as exc:
            if not ok:
                raise ServiceFailure(f"service {name} failed in its node: {values}") from None
            where = validation_reason(exc, "response")
            raise NodeFailure(f"service {name}: the node's answer is not a {service.type} response ({where})") from None

    def _effect(self, name: str, request: RosMessage) -> None:
        """A node's answer of a service with an effect (start/stop): the lab applies its meaning."""
        effect = self.effects.get(name)
        if effect is not None:
            effect(self.lab, request)


def models_of(type_name: str, text: str) -> tuple[type[RosMessage], type[RosMessage]]:
    """(request, response) models of a node's carried .srv text; ServiceFailure with the reason it
    cannot be read (a rosbridge session builds them in a worker thread, off its event loop)."""
    try:
        return service_models(type_name, text)
    except BadDefinition as exc:
        raise ServiceFailure(f"the definition of {type_name} cannot be read: {exc}") from None


def _lines(text: str) -> list[str]:
    """A definition's `type name` lines, comments and blanks left out."""
    return [line.split("#")[0].strip() for line in text.splitlines() if line.split("#")[0].strip()]


def _fail(future: Future, error: Exception) -> None:
    if not future.done():
        future.set_exception(error)
