"""rospy (ROS 1's Python client library) over the lab's rosbridge endpoint.

The API the rospy handouts use, with rospy's threading: a subscriber's callbacks run on its own
thread, each service call on a thread of its own, the main thread is free (spin() only waits).
Ctrl+C shuts the node down (spin() returns, sleep()/Rate.sleep() raise ROSInterruptException), as
rospy's signal handler does. Names: `~x` is private (/node/x), `x` relative to the root
namespace. Differences from ROS 1: docs/ros-programs-client.md.
"""
from __future__ import annotations

import math
import os
import signal
import sys
import threading
import time
import traceback
from collections import deque
from typing import Any, Callable

from app.rosclient import process
from app.rosclient.connection import RosbridgeError
from app.rosclient.interfaces import Message, full_text

__all__ = ["init_node", "Service", "ServiceProxy", "wait_for_service", "Publisher", "Subscriber", "spin", "Rate",
           "sleep", "is_shutdown", "signal_shutdown", "on_shutdown", "get_time", "Time", "Duration", "loginfo",
           "logwarn", "logerr", "logdebug", "logfatal", "get_param", "set_param", "has_param", "delete_param",
           "ROSException", "ROSInterruptException", "ServiceException", "get_name", "myargv", "wait_for_message"]

DEBUG, INFO, WARN, ERROR, FATAL = 1, 2, 4, 8, 16  # rosgraph_msgs/Log levels
_LEVEL_NAMES = {DEBUG: "DEBUG", INFO: "INFO", WARN: "WARN", ERROR: "ERROR", FATAL: "FATAL"}


class ROSException(Exception):
    """rospy's base exception (e.g. wait_for_service's timeout)."""


class ROSInitException(ROSException):
    pass


class ROSInterruptException(ROSException, KeyboardInterrupt):
    """Raised by sleep() and Rate.sleep() when the node shuts down."""


class ROSInternalException(Exception):
    pass


class ServiceException(Exception):
    """A service call that failed (the service is missing, its handler failed, or the lab refused it)."""


class TransportException(ROSException):
    pass


_node: dict[str, Any] = {"name": None, "level": INFO}
_shutdown_hooks: list[Callable] = []
_hooks_lock = threading.Lock()


# --- time ---------------------------------------------------------------------------------------
class _TVal:
    __slots__ = ("secs", "nsecs")

    def __init__(self, secs: int | float = 0, nsecs: int = 0) -> None:
        if isinstance(secs, float):
            whole = math.floor(secs)
            nsecs += int(round((secs - whole) * 1e9))
            secs = whole
        total = int(secs) * 10**9 + int(nsecs)
        self.secs, self.nsecs = divmod(total, 10**9) if total >= 0 or type(self) is Time else _split_negative(total)

    @classmethod
    def from_sec(cls, float_secs: float):
        return cls(float(float_secs))

    @classmethod
    def from_seconds(cls, float_secs: float):
        return cls(float(float_secs))

    def to_sec(self) -> float:
        return self.secs + self.nsecs * 1e-9

    def to_nsec(self) -> int:
        return self.secs * 10**9 + self.nsecs

    def is_zero(self) -> bool:
        return self.secs == 0 and self.nsecs == 0

    def __float__(self) -> float:
        return self.to_sec()

    def __eq__(self, other: Any) -> bool:
        return hasattr(other, "to_nsec") and self.to_nsec() == other.to_nsec()

    def __lt__(self, other: Any) -> bool:
        return self.to_nsec() < other.to_nsec()

    def __le__(self, other: Any) -> bool:
        return self.to_nsec() <= other.to_nsec()

    def __gt__(self, other: Any) -> bool:
        return self.to_nsec() > other.to_nsec()

    def __ge__(self, other: Any) -> bool:
        return self.to_nsec() >= other.to_nsec()

    def __hash__(self) -> int:
        return hash(self.to_nsec())

    def __repr__(self) -> str:
        return f"rospy.{type(self).__name__}[{self.to_nsec()}]"

    __str__ = lambda self: str(self.to_nsec())  # noqa: E731 - genpy prints nanoseconds


def _split_negative(total: int) -> tuple[int, int]:
    secs = int(total / 10**9)
    return secs, total - secs * 10**9


class Duration(_TVal):
    __slots__ = ()

    def __add__(self, other: Any):
        if isinstance(other, Time):
            return Time(0, self.to_nsec() + other.to_nsec())
        return Duration(0, self.to_nsec() + other.to_nsec())

    __radd__ = __add__

    def __sub__(self, other: "Duration") -> "Duration":
        return Duration(0, self.to_nsec() - other.to_nsec())

    def __neg__(self) -> "Duration":
        return Duration(0, -self.to_nsec())

    def __mul__(self, k: float) -> "Duration":
        return Duration(0, int(self.to_nsec() * k))

    __rmul__ = __mul__

    def __truediv__(self, k: Any):
        if isinstance(k, Duration):
            return self.to_nsec() / k.to_nsec()
        return Duration(0, int(self.to_nsec() / k))


class Time(_TVal):
    __slots__ = ()

    @classmethod
    def now(cls) -> "Time":
        return cls(0, time.time_ns())

    def __add__(self, other: Duration) -> "Time":
        return Time(0, self.to_nsec() + other.to_nsec())

    def __sub__(self, other: Any):
        if isinstance(other, Time):
            return Duration(0, self.to_nsec() - other.to_nsec())
        return Time(0, self.to_nsec() - other.to_nsec())


def get_time() -> float:
    return time.time()


def get_rostime() -> Time:
    return Time.now()


def sleep(duration: float | Duration) -> None:
    """Wall-clock sleep; ROSInterruptException when the node shuts down meanwhile."""
    seconds = duration.to_sec() if isinstance(duration, Duration) else float(duration)
    if process.shutdown_event.wait(max(seconds, 0.0)):
        raise ROSInterruptException("ROS shutdown request")


class Rate:
    """Sleeps to keep a loop at `hz` (a late loop starts the next period now, as rospy does)."""

    def __init__(self, hz: float, reset: bool = False) -> None:
        self.period = 1.0 / hz
        self.last = time.monotonic()

    def remaining(self) -> Duration:
        return Duration(max(self.last + self.period - time.monotonic(), 0.0))

    def sleep(self) -> None:
        now = time.monotonic()
        wait = self.last + self.period - now
        self.last = self.last + self.period if wait > 0 or now - self.last < 2 * self.period else now
        if wait > 0 and process.shutdown_event.wait(wait):
            raise ROSInterruptException("ROS shutdown request")
        if process.shutdown_event.is_set():
            raise ROSInterruptException("ROS shutdown request")


class Timer:
    """rospy.Timer(period, callback): calls callback(TimerEvent) every period on its own thread."""

    def __init__(self, period: Duration, callback: Callable, oneshot: bool = False, reset: bool = False) -> None:
        self.period, self.callback, self.oneshot = period, callback, oneshot
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True, name="rospy-timer")
        self._thread.start()

    def _run(self) -> None:
        last = Time.now()
        while not self._stop.wait(self.period.to_sec()) and not process.shutdown_event.is_set():
            now = Time.now()
            self.callback(TimerEvent(last, now, now, now, now - last))
            last = now
            if self.oneshot:
                break

    def shutdown(self) -> None:
        self._stop.set()


class TimerEvent:
    def __init__(self, last_expected, last_real, current_expected, current_real, last_duration) -> None:
        self.last_expected, self.last_real = last_expected, last_real
        self.current_expected, self.current_real = current_expected, current_real
        self.last_duration = last_duration


# --- node ---------------------------------------------------------------------------------------
def init_node(name: str, argv: list[str] | None = None, anonymous: bool = False, log_level: int | None = None,
              disable_rostime: bool = False, disable_rosout: bool = False, disable_signals: bool = False,
              xmlrpc_port: int = 0, tcpros_port: int = 0) -> None:
    if _node["name"] is not None:
        raise ROSException("rospy.init_node() has already been called with different arguments: "
                           f"{_node['name']}")
    if "/" in name.strip("/"):
        raise ValueError("namespaces are not allowed in node names")
    args = sys.argv if argv is None else argv
    remapped = [a for a in args[1:] if ":=" in a]
    for arg in remapped:
        key, value = arg.split(":=", 1)
        if key == "__name":
            name = value
    base = name.strip("/")
    if anonymous:
        base = f"{base}_{os.getpid()}_{int(time.time() * 1000)}"
    _node["name"] = "/" + base
    if log_level is not None:
        _node["level"] = log_level
    _node["rosout"] = not disable_rosout
    process.connection()
    if not disable_signals and threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, lambda signum, frame: signal_shutdown("keyboard interrupt"))
        signal.signal(signal.SIGTERM, lambda signum, frame: signal_shutdown("terminated"))
    for arg in remapped:  # _name:=value sets the private parameter ~name; name:=other remaps a name
        key, value = arg.split(":=", 1)
        if key.startswith("_") and not key.startswith("__"):
            set_param("~" + key[1:], process.parse_value(value))
        elif not key.startswith("_"):
            process.remaps[process.resolve(key, _node["name"])] = process.resolve(value, _node["name"])


def get_name() -> str:
    return _node["name"] or "/unnamed"


get_caller_id = get_name


def get_namespace() -> str:
    return "/"


def myargv(argv: list[str] | None = None) -> list[str]:
    """argv without ROS remapping arguments (name:=value)."""
    return [a for a in (sys.argv if argv is None else argv) if ":=" not in a]


def resolve_name(name: str, caller_id: str | None = None) -> str:
    return process.resolve(name, get_name() if _node["name"] else "")


def _require_node(what: str) -> None:
    if _node["name"] is None:
        raise ROSInitException(f"{what}: call rospy.init_node() first")


def is_shutdown() -> bool:
    return process.shutdown_event.is_set()


def core_is_shutdown() -> bool:  # pragma: no cover - alias
    return is_shutdown()


def on_shutdown(hook: Callable) -> None:
    with _hooks_lock:
        _shutdown_hooks.append(hook)


def signal_shutdown(reason: str) -> None:
    if process.shutdown_event.is_set():
        return
    process.shutdown(reason)
    with _hooks_lock:
        hooks = list(_shutdown_hooks)
    for hook in hooks:
        try:
            hook()
        except Exception:  # noqa: BLE001 - rospy logs a failing hook and goes on
            traceback.print_exc()


def spin() -> None:
    """Wait until the node shuts down (Ctrl+C); callbacks run on their own threads meanwhile."""
    _require_node("rospy.spin")
    try:
        while not process.shutdown_event.wait(0.2):
            pass
    except KeyboardInterrupt:
        signal_shutdown("keyboard interrupt")


# --- logging ------------------------------------------------------------------------------------
def _log(level: int, msg: Any, *args: Any, **kwargs: Any) -> None:
    text = str(msg) % args if args else str(msg)
    if level < _node["level"]:
        return
    now = time.time()
    stream = sys.stdout if level <= INFO else sys.stderr
    print(f"[{_LEVEL_NAMES[level]}] [{now:.6f}]: {text}", file=stream, flush=True)
    if _node["name"] is not None and _node.get("rosout", True):
        caller = sys._getframe(2)
        process.rosout({"header": {"stamp": process.stamp_now(), "frame_id": ""}, "level": level,
                        "name": get_name(), "msg": text, "file": os.path.basename(caller.f_code.co_filename),
                        "function": caller.f_code.co_name, "line": caller.f_lineno, "topics": []},
                       "rosgraph_msgs/Log")


def logdebug(msg: Any, *args: Any, **kwargs: Any) -> None:
    _log(DEBUG, msg, *args)


def loginfo(msg: Any, *args: Any, **kwargs: Any) -> None:
    _log(INFO, msg, *args)


def logwarn(msg: Any, *args: Any, **kwargs: Any) -> None:
    _log(WARN, msg, *args)


def logerr(msg: Any, *args: Any, **kwargs: Any) -> None:
    _log(ERROR, msg, *args)


def logfatal(msg: Any, *args: Any, **kwargs: Any) -> None:
    _log(FATAL, msg, *args)


_throttled: dict[tuple, float] = {}


def _throttle(level: int, period: float, msg: Any, *args: Any) -> None:
    caller = sys._getframe(2)
    key = (caller.f_code.co_filename, caller.f_lineno)
    now = time.monotonic()
    if now - _throttled.get(key, -math.inf) >= period:
        _throttled[key] = now
        _log(level, msg, *args)


def loginfo_throttle(period: float, msg: Any, *args: Any) -> None:
    _throttle(INFO, period, msg, *args)


def logwarn_throttle(period: float, msg: Any, *args: Any) -> None:
    _throttle(WARN, period, msg, *args)


def logerr_throttle(period: float, msg: Any, *args: Any) -> None:
    _throttle(ERROR, period, msg, *args)


logwarning = logwarn
logerror = logerr


# --- parameters (the lab's parameter server, through rosapi) ------------------------------------
class _Unspecified:
    pass


_unspecified = _Unspecified()


def _param_name(name: str) -> str:
    return process.resolve(name, get_name())


def has_param(param_name: str) -> bool:
    return bool(_rosapi("has_param", {"name": _param_name(param_name)}).get("exists"))


def get_param(param_name: str, default: Any = _unspecified) -> Any:
    """The value; the default when it is not set; KeyError when neither."""
    import json

    name = _param_name(param_name)
    if not has_param(name):
        if default is _unspecified:
            raise KeyError(param_name)
        return default
    return json.loads(_rosapi("get_param", {"name": name, "default_value": ""})["value"])


def get_param_cached(param_name: str, default: Any = _unspecified) -> Any:
    return get_param(param_name, default)


def set_param(param_name: str, param_value: Any) -> None:
    import json

    _rosapi("set_param", {"name": _param_name(param_name), "value": json.dumps(param_value)})


def delete_param(param_name: str) -> None:
    name = _param_name(param_name)
    if not has_param(name):
        raise KeyError(param_name)
    _rosapi("delete_param", {"name": name})


def get_param_names() -> list[str]:
    return list(_rosapi("get_param_names", {}).get("names", []))


def search_param(param_name: str) -> str | None:
    name = _param_name(param_name)
    return name if has_param(name) else None


def _rosapi(service: str, args: dict) -> dict:
    try:
        return process.connection().call_service(f"/rosapi/{service}", args, timeout=10)
    except RosbridgeError as exc:
        raise ROSException(f"parameter server: {exc}") from None


# --- topics -------------------------------------------------------------------------------------
class Publisher:
    def __init__(self, name: str, data_class: type, subscriber_listener: Any = None, tcp_nodelay: bool = False,
                 latch: bool = False, headers: Any = None, queue_size: int | None = None) -> None:
        _check_class(data_class, "rospy.Publisher")
        self.name = process.resolve(name, get_name())
        self.resolved_name = self.name
        self.data_class, self.type = data_class, data_class._type
        process.advertise_once(self.name, self.type, data_class)

    def publish(self, *args: Any, **kwds: Any) -> None:
        if process.shutdown_event.is_set():
            raise ROSException("publish() to a closed topic")
        if len(args) == 1 and not kwds and isinstance(args[0], Message):
            msg = args[0]
            if not isinstance(msg, self.data_class):
                raise ROSSerializationException(f"expected {self.type} for {self.name}, got {msg._type}")
        else:
            msg = self.data_class(*args, **kwds)
        try:
            data = msg.to_json()
        except (TypeError, ValueError) as exc:
            raise ROSSerializationException(str(exc)) from None
        process.publish(self.name, self.type, data)

    def get_num_connections(self) -> int:
        return 1

    def unregister(self) -> None:
        process.connection().send({"op": "unadvertise", "topic": self.name})


class ROSSerializationException(ROSException):
    pass


class Subscriber:
    """Messages into a queue of `queue_size` (None: unbounded; full: the oldest dropped), handed to
    the callback on this subscriber's own thread."""

    def __init__(self, name: str, data_class: type, callback: Callable | None = None, callback_args: Any = None,
                 queue_size: int | None = None, buff_size: int = 65536, tcp_nodelay: bool = False) -> None:
        _check_class(data_class, "rospy.Subscriber")
        self.name = process.resolve(name, get_name())
        self.resolved_name = self.name
        self.data_class, self.callback, self.callback_args = data_class, callback, callback_args
        self.queue: deque = deque(maxlen=queue_size if queue_size and queue_size > 0 else None)
        self.received = 0
        self._ready = threading.Condition()
        self._closed = False
        threading.Thread(target=self._deliver, daemon=True, name=f"rospy-sub{self.name}").start()
        self._sid = process.connection().subscribe(self.name, data_class._type, self._offer,
                                                   queue_length=queue_size or 0)

    def _offer(self, data: dict) -> None:
        with self._ready:
            self.received += 1
            self.queue.append(data)
            self._ready.notify()

    def _deliver(self) -> None:
        while True:
            with self._ready:
                while not self.queue and not self._closed:
                    self._ready.wait()
                if self._closed:
                    return
                data = self.queue.popleft()
            if self.callback is None:
                continue
            if process.shutdown_event.is_set():  # the program is ending: no new callback
                return
            try:
                with process.running_callback():
                    msg = self.data_class.from_json(data)
                    if self.callback_args is None:
                        self.callback(msg)
                    else:
                        self.callback(msg, self.callback_args)
            except Exception:  # noqa: BLE001 - rospy logs a failing callback, the subscriber goes on
                logerr("bad callback: %s\n%s", self.callback, traceback.format_exc())

    def get_num_connections(self) -> int:
        return 1

    def unregister(self) -> None:
        with self._ready:
            self._closed = True
            self._ready.notify()
        process.connection().unsubscribe(self.name, self._sid, self._offer)


def wait_for_message(topic: str, topic_type: type, timeout: float | None = None) -> Any:
    got: list = []
    event = threading.Event()

    def take(msg: Any) -> None:
        if not got:
            got.append(msg)
            event.set()

    sub = Subscriber(topic, topic_type, take)
    try:
        if not event.wait(timeout) or not got:
            raise ROSException(f"timeout exceeded while waiting for message on topic {topic}")
        return got[0]
    finally:
        sub.unregister()


def _check_class(data_class: Any, what: str) -> None:
    if not (isinstance(data_class, type) and issubclass(data_class, Message)):
        raise ValueError(f"{what}: data_class must be a message class (e.g. std_msgs.msg.String), got {data_class!r}")


# --- services -----------------------------------------------------------------------------------
def _service_class(service_class: Any, what: str) -> Any:
    if not hasattr(service_class, "_request_class"):
        raise ValueError(f"{what}: service_class must be a service type (e.g. from my_pkg.srv import AddTwoInts), "
                         f"got {service_class!r}")
    return service_class


def wait_for_service(service: str, timeout: float | None = None) -> None:
    """Block until the service is advertised in the lab; ROSException after `timeout` s."""
    name = process.resolve(service, get_name())
    if not process.wait_until(lambda: name in process.service_names(), timeout):
        if process.shutdown_event.is_set():
            raise ROSInterruptException("rospy shutdown")
        raise ROSException(f"timeout exceeded while waiting for service {name}")


class ServiceProxy:
    def __init__(self, name: str, service_class: Any, persistent: bool = False, headers: Any = None) -> None:
        self.service_class = _service_class(service_class, "rospy.ServiceProxy")
        self.resolved_name = process.resolve(name, get_name())
        self.request_class = service_class._request_class
        self.response_class = service_class._response_class

    def __call__(self, *args: Any, **kwds: Any) -> Any:
        return self.call(*args, **kwds)

    def call(self, *args: Any, **kwds: Any) -> Any:
        if len(args) == 1 and not kwds and isinstance(args[0], self.request_class):
            request = args[0]
        else:
            request = self.request_class(*args, **kwds)
        try:
            values = process.connection().call_service(self.resolved_name, request.to_json())
        except RosbridgeError as exc:
            raise ServiceException(f"service [{self.resolved_name}] failed: {exc}") from None
        try:
            return self.response_class.from_json(values if values is not None else {})
        except (TypeError, ValueError) as exc:
            raise ServiceException(f"service [{self.resolved_name}] answered with a bad response: {exc}") from None

    def close(self) -> None:
        pass


class ServiceProxyWrapper(ServiceProxy):  # pragma: no cover - name only
    pass


class Service:
    """A service this node provides; every call runs the handler on a thread of its own."""

    def __init__(self, name: str, service_class: Any, handler: Callable, buff_size: int = 65536,
                 error_handler: Callable | None = None) -> None:
        _require_node("rospy.Service")
        self.service_class = _service_class(service_class, "rospy.Service")
        self.resolved_name = process.resolve(name, get_name())
        self.handler = handler
        process.connection().advertise_service(
            self.resolved_name, service_class._type, self._on_call, full_text(service_class)
        )

    def _on_call(self, message: dict) -> None:
        threading.Thread(target=self._serve, args=(message,), daemon=True, name="rospy-service").start()

    def _serve(self, message: dict) -> None:
        with process.running_callback():
            self._answer(message)

    def _answer(self, message: dict) -> None:
        connection = process.connection()
        try:
            request = self.service_class._request_class.from_json(message.get("args") or {})
            response = _as_response(self.service_class._response_class, self.handler(request))
            connection.service_response(message.get("id"), self.resolved_name, response.to_json(), True)
        except ServiceException as exc:
            connection.service_response(message.get("id"), self.resolved_name, str(exc), False)
        except Exception as exc:  # noqa: BLE001 - rospy: "error processing request", logged
            logerr("Error processing request: %s\n%s", exc, traceback.format_exc())
            connection.service_response(message.get("id"), self.resolved_name,
                                        f"error processing request: {exc}", False)

    def shutdown(self, reason: str = "") -> None:
        process.connection().send({"op": "unadvertise_service", "service": self.resolved_name})

    def spin(self) -> None:
        spin()


def _as_response(response_class: type, value: Any) -> Message:
    """What a handler may return, as rospy takes it: the response, a dict of its fields, a tuple or
    list of them in order, or the value of a single-field response."""
    if isinstance(value, response_class):
        return value
    if value is None:
        raise ServiceException("service handler returned None")
    if isinstance(value, Message):
        raise ServiceException(f"service handler returned a {value._type}, not a {response_class._type}")
    if isinstance(value, dict):
        return response_class(**value)
    if isinstance(value, (list, tuple)):
        return response_class(*value)
    if len(response_class._fields) == 1:
        return response_class(value)
    raise ServiceException(f"service handler returned {value!r}, not a {response_class._type}")
