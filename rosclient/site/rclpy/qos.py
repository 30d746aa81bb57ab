"""rclpy.qos: the profiles programs pass. The history depth is the subscription's queue (full, the
oldest message is dropped); durability, lifespan, deadline and liveliness are kept as rclpy keeps
them, for the events rclpy/event_handler.py computes and the late joiners of TRANSIENT_LOCAL
publishers; `qos_check_compatible` is rmw's rule of which publisher a subscription may hear."""
from __future__ import annotations

from enum import IntEnum

from rclpy.duration import Duration


class HistoryPolicy(IntEnum):
    SYSTEM_DEFAULT = 0
    KEEP_LAST = 1
    KEEP_ALL = 2
    UNKNOWN = 3


class ReliabilityPolicy(IntEnum):
    SYSTEM_DEFAULT = 0
    RELIABLE = 1
    BEST_EFFORT = 2
    UNKNOWN = 3


class DurabilityPolicy(IntEnum):
    SYSTEM_DEFAULT = 0
    TRANSIENT_LOCAL = 1
    VOLATILE = 2
    UNKNOWN = 3


class LivelinessPolicy(IntEnum):
    SYSTEM_DEFAULT = 0
    AUTOMATIC = 1
    MANUAL_BY_TOPIC = 3
    UNKNOWN = 4


QoSHistoryPolicy, QoSReliabilityPolicy, QoSDurabilityPolicy = HistoryPolicy, ReliabilityPolicy, DurabilityPolicy
QoSLivelinessPolicy = LivelinessPolicy


class QoSPolicyKind(IntEnum):
    INVALID = 1 << 0
    DURABILITY = 1 << 1
    DEADLINE = 1 << 2
    LIVELINESS = 1 << 3
    RELIABILITY = 1 << 4
    HISTORY = 1 << 5
    LIFESPAN = 1 << 6
    DEPTH = 1 << 7
    LIVELINESS_LEASE_DURATION = 1 << 8
    AVOID_ROS_NAMESPACE_CONVENTIONS = 1 << 9


def qos_policy_name_from_kind(policy_kind: QoSPolicyKind | int) -> str:
    return QoSPolicyKind(policy_kind).name


class QoSProfile:
    """A profile's policies; a Duration of 0 (the default) is rmw's 'default': infinite."""

    def __init__(self, *, history: HistoryPolicy = HistoryPolicy.KEEP_LAST, depth: int | None = None,
                 reliability: ReliabilityPolicy = ReliabilityPolicy.RELIABLE,
                 durability: DurabilityPolicy = DurabilityPolicy.VOLATILE, lifespan: Duration | None = None,
                 deadline: Duration | None = None, liveliness: LivelinessPolicy = LivelinessPolicy.SYSTEM_DEFAULT,
                 liveliness_lease_duration: Duration | None = None, avoid_ros_namespace_conventions: bool = False,
                 **other) -> None:
        if history == HistoryPolicy.KEEP_LAST and depth is None:
            raise ValueError("A QoSProfile with history KEEP_LAST needs a depth")
        self.history, self.depth, self.reliability, self.durability = history, depth or 0, reliability, durability
        self.lifespan, self.deadline = lifespan or Duration(), deadline or Duration()
        self.liveliness, self.liveliness_lease_duration = liveliness, liveliness_lease_duration or Duration()
        self.avoid_ros_namespace_conventions = avoid_ros_namespace_conventions
        for key, value in other.items():
            setattr(self, key, value)

    def __repr__(self) -> str:
        return (f"QoSProfile(history={self.history!r}, depth={self.depth}, reliability={self.reliability!r}, "
                f"durability={self.durability!r}, lifespan={self.lifespan!r}, deadline={self.deadline!r}, "
                f"liveliness={self.liveliness!r}, liveliness_lease_duration={self.liveliness_lease_duration!r})")

    @property
    def queue_length(self) -> int:
        """rosbridge's queue_length: KEEP_ALL is unbounded (0)."""
        return 0 if self.history == HistoryPolicy.KEEP_ALL else self.depth


class QoSCompatibility(IntEnum):
    OK = 0
    WARNING = 1
    ERROR = 2


def incompatible_policies(publisher: QoSProfile, subscription: QoSProfile) -> list[QoSPolicyKind]:
    """The policies by which `subscription` cannot hear `publisher`, in the order rmw checks them
    (rmw/qos_profiles.c: the offered kind below the requested one, an offered period longer than the
    requested one; a Duration of 0 is infinite)."""
    out = []
    if publisher.reliability == ReliabilityPolicy.BEST_EFFORT and subscription.reliability == ReliabilityPolicy.RELIABLE:
        out.append(QoSPolicyKind.RELIABILITY)
    if publisher.durability == DurabilityPolicy.VOLATILE and subscription.durability == DurabilityPolicy.TRANSIENT_LOCAL:
        out.append(QoSPolicyKind.DURABILITY)
    if _longer(publisher.deadline, subscription.deadline):
        out.append(QoSPolicyKind.DEADLINE)
    if publisher.liveliness in (LivelinessPolicy.AUTOMATIC, LivelinessPolicy.SYSTEM_DEFAULT) and \
            subscription.liveliness == LivelinessPolicy.MANUAL_BY_TOPIC:
        out.append(QoSPolicyKind.LIVELINESS)
    if _longer(publisher.liveliness_lease_duration, subscription.liveliness_lease_duration):
        out.append(QoSPolicyKind.LIVELINESS_LEASE_DURATION)
    return out


def _longer(offered: Duration, requested: Duration) -> bool:
    """An offered period longer than a finite requested one (0: infinite)."""
    return requested.nanoseconds > 0 and (offered.nanoseconds == 0 or offered.nanoseconds > requested.nanoseconds)


def qos_check_compatible(publisher_qos: QoSProfile, subscription_qos: QoSProfile) -> tuple[QoSCompatibility, str]:
    """rclpy's check: ERROR with the reason when the subscription cannot hear the publisher."""
    policies = incompatible_policies(publisher_qos, subscription_qos)
    if not policies:
        return QoSCompatibility.OK, ""
    return QoSCompatibility.ERROR, "; ".join(f"incompatible {p.name.lower()}" for p in policies)


def profile(qos) -> QoSProfile:
    if isinstance(qos, QoSProfile):
        return qos
    if isinstance(qos, int) and not isinstance(qos, bool):
        if qos < 0:
            raise ValueError("qos_profile: a history depth must be >= 0")
        return QoSProfile(depth=qos)
    raise TypeError(f"qos_profile must be a QoSProfile or an int (the history depth), got {qos!r}")


qos_profile_sensor_data = QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT)
qos_profile_system_default = QoSProfile(depth=10)
qos_profile_services_default = QoSProfile(depth=10)
qos_profile_parameters = QoSProfile(depth=1000)
qos_profile_parameter_events = QoSProfile(depth=1000)
qos_profile_action_status_default = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)


class QoSPresetProfiles:
    SENSOR_DATA = qos_profile_sensor_data
    SYSTEM_DEFAULT = qos_profile_system_default
    SERVICES_DEFAULT = qos_profile_services_default
    PARAMETERS = qos_profile_parameters
    PARAMETER_EVENTS = qos_profile_parameter_events
