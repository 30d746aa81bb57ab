"""rospy (ROS 1's Python client library) over the lab's rosbridge endpoint, laid out as rospy is:
names.py (ROS 1 names), client.py (init_node, spin, parameters), core.py (shutdown, logging),
rostime.py, timer.py (sleep, Rate, Timer), topics.py (Publisher, Subscriber), service.py and
impl/tcpros_service.py (services), exceptions.py.

The API the rospy handouts use, with rospy's threading: a subscriber's callbacks run on its own
thread, each service call on a thread of its own, the main thread is free (spin() only waits).
Ctrl+C shuts the node down (spin() returns, sleep()/Rate.sleep() raise ROSInterruptException), as
rospy's signal handler does. Differences from ROS 1: docs/ros-programs-client.md.
"""

from rosclient import process
from rospy.client import (
    DEBUG,
    ERROR,
    FATAL,
    INFO,
    WARN,
    delete_param,
    get_master,
    get_param,
    get_param_cached,
    get_param_names,
    get_published_topics,
    has_param,
    init_node,
    myargv,
    search_param,
    set_param,
    spin,
    wait_for_message,
)
from rospy.core import (
    get_node_uri,
    is_initialized,
    is_shutdown,
    is_shutdown_requested,
    logdebug,
    logdebug_once,
    logdebug_throttle,
    logerr,
    logerr_once,
    logerr_throttle,
    logerror,
    logfatal,
    logfatal_once,
    logfatal_throttle,
    loginfo,
    loginfo_once,
    loginfo_throttle,
    logout,
    logwarn,
    logwarn_once,
    logwarn_throttle,
    logwarning,
    on_shutdown,
    signal_shutdown,
)
from rospy.exceptions import (
    ROSException,
    ROSInitException,
    ROSInternalException,
    ROSInterruptException,
    ROSSerializationException,
    ROSTimeMovedBackwardsException,
    TransportException,
)
from rospy.impl.tcpros_service import Service, ServiceProxy, wait_for_service
from rospy.names import get_caller_id, get_name, get_namespace, remap_name, resolve_name
from rospy.rostime import Duration, Time, get_rostime, get_time
from rospy.service import ServiceException
from rospy.timer import Rate, Timer, TimerEvent, sleep
from rospy.topics import Publisher, SubscribeListener, Subscriber

process.use_ros1()  # ROS 1's Header (with seq) for the messages this program makes from now on

from std_msgs.msg import Header  # noqa: E402 - rospy's own export (`from rospy import Header`, as actionlib has it)


__all__ = [
    "DEBUG", "INFO", "WARN", "ERROR", "FATAL",
    "init_node", "spin", "myargv", "get_master", "get_published_topics", "wait_for_message",
    "get_param", "get_param_cached", "set_param", "has_param", "delete_param", "get_param_names", "search_param",
    "is_initialized", "is_shutdown", "is_shutdown_requested", "on_shutdown", "signal_shutdown", "get_node_uri",
    "logdebug", "loginfo", "logwarn", "logerr", "logfatal", "logwarning", "logerror", "logout",
    "logdebug_throttle", "loginfo_throttle", "logwarn_throttle", "logerr_throttle", "logfatal_throttle",
    "logdebug_once", "loginfo_once", "logwarn_once", "logerr_once", "logfatal_once",
    "ROSException", "ROSInitException", "ROSInternalException", "ROSInterruptException",
    "ROSSerializationException", "ROSTimeMovedBackwardsException", "TransportException", "ServiceException",
    "Service", "ServiceProxy", "wait_for_service",
    "get_name", "get_caller_id", "get_namespace", "resolve_name", "remap_name",
    "Time", "Duration", "get_rostime", "get_time", "Rate", "Timer", "TimerEvent", "sleep",
    "Publisher", "Subscriber", "SubscribeListener", "Header",
]  # fmt: skip
