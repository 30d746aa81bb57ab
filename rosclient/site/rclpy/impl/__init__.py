"""rclpy.impl: what rclpy keeps below its public modules (here: the logging severities)."""
