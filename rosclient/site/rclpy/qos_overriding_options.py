"""rclpy.qos_overriding_options: a publisher's or subscription's QoS policies as read-only
parameters (`qos_overrides./TOPIC.publisher.depth`, ...), their values from the node's overrides
(`--ros-args -p` or a parameter file) put in the profile, a callback to accept them."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any

from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSPolicyKind, QoSProfile, ReliabilityPolicy


class InvalidQosOverridesError(Exception):
    pass


class QosCallbackResult:
    def __init__(self, successful: bool = True, reason: str = "") -> None:
        self.successful, self.reason = successful, reason


class QoSOverridingOptions:
    def __init__(self, policy_kinds: Iterable[QoSPolicyKind], *, callback: Callable[[QoSProfile], Any] | None = None,
                 entity_id: str | None = None) -> None:
        self.policy_kinds = list(policy_kinds)
        self.callback = callback
        self.entity_id = entity_id

    @classmethod
    def with_default_policies(cls, *, callback: Callable[[QoSProfile], Any] | None = None,
                              entity_id: str | None = None) -> QoSOverridingOptions:
        return cls((QoSPolicyKind.HISTORY, QoSPolicyKind.DEPTH, QoSPolicyKind.RELIABILITY), callback=callback,
                   entity_id=entity_id)

    @property
    def _qos_callback(self) -> Callable[[QoSProfile], Any] | None:
        return self.callback


_ENUMS: dict[QoSPolicyKind, tuple[str, Any]] = {
    QoSPolicyKind.HISTORY: ("history", HistoryPolicy),
    QoSPolicyKind.RELIABILITY: ("reliability", ReliabilityPolicy),
    QoSPolicyKind.DURABILITY: ("durability", DurabilityPolicy),
}


def _declare_qos_parameters(entity_type: str, node: Any, topic_name: str, qos: QoSProfile,
                            options: QoSOverridingOptions) -> None:
    """Declares `qos_overrides.<topic>.<entity_type>[_<entity_id>].<policy>` for each policy kind, puts the
    values given in `qos`, and asks the callback (InvalidQosOverridesError when it refuses)."""
    from rcl_interfaces.msg import ParameterDescriptor

    entity = f"{entity_type}_{options.entity_id}" if options.entity_id else entity_type
    for kind in options.policy_kinds:
        if kind == QoSPolicyKind.DEPTH:
            name, current = "depth", int(qos.depth)
        elif kind in _ENUMS:
            name, _ = _ENUMS[kind]
            current = getattr(qos, name).name.lower()
        else:
            raise InvalidQosOverridesError(f"overriding the QoS policy {kind.name} is not supported here")
        parameter = f"qos_overrides.{topic_name}.{entity}.{name}"
        descriptor = ParameterDescriptor(description=f"QoS policy {name} of {topic_name}", read_only=True)
        value = node.declare_parameter(parameter, current, descriptor).value
        if kind == QoSPolicyKind.DEPTH:
            qos.depth = int(value)
        else:
            enum = _ENUMS[kind][1]
            try:
                setattr(qos, name, enum[str(value).upper()])
            except KeyError:
                raise InvalidQosOverridesError(f"{parameter}: {value!r} is not a {name} policy") from None
    if options.callback is not None:
        result = options.callback(qos)
        if not getattr(result, "successful", True):
            raise InvalidQosOverridesError(f"the callback refused the QoS: {getattr(result, 'reason', '')}")
