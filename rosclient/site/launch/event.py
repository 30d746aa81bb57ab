"""launch.event: what every event of a launch is (launch.events holds the kinds: Shutdown, process's)."""

from __future__ import annotations


class Event:
    name = "launch.Event"
