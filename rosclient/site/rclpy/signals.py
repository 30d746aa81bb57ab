"""rclpy.signals: which signal handlers rclpy.init() installs."""

from rclpy import SignalHandlerOptions

__all__ = ["SignalHandlerOptions"]
