"""Every command the server sends into the mobile world (`lab.call(fn, *args)`, as app/lab/commands.py
for the lifting world): module-level functions fn(world, *args), run between two steps."""

from __future__ import annotations

from sim.mobile.world import MobileWorld


def drive(world: MobileWorld, twist: list[float]) -> None:
    """A geometry_msgs/Twist on /cmd_vel as [vx, vy, vz, wx, wy, wz]: a differential-drive base
    follows linear.x and angular.z (the others are ignored, as the TurtleBot3's node does)."""
    world.drive(float(twist[0]), float(twist[5]))


def reset(world: MobileWorld) -> None:
    """The base back at its start pose, the odometry and the trial's monitor restarted."""
    world.reset()
