"""What the lab logs on its own, on /rosout, as it happens: a reflex that stops the robot and its
recovery, a trial's end, a restart of the simulation. Read from the published snapshots and the
supervisor's figures (never from inside the simulation), every PERIOD_S."""

from __future__ import annotations

import threading
from typing import TYPE_CHECKING

from app.ros.names import LAB_NODE, node_name

if TYPE_CHECKING:
    from sim.world import Snapshot

    from app.worlds.port import LabPort

PERIOD_S = 0.05


class LabEvents:
    def __init__(self, lab: LabPort[Snapshot]) -> None:
        self.lab = lab
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def start(self) -> None:
        self._stop.clear()
        self._thread = threading.Thread(target=self._run, name="lab-events", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=5)

    def _run(self) -> None:
        lab = self.lab
        error, trial, restarts = None, "none", lab.runtime.restarts
        while not self._stop.wait(PERIOD_S):
            try:
                snapshot = lab.snapshot()
            except Exception:  # noqa: BLE001 - the process is being restarted: read again later
                continue
            if snapshot.error != error:
                if snapshot.error:
                    lab.rosout.log(
                        "franka_control", f"reflex: {snapshot.error} (the robot stopped; call /error_recovery)", "ERROR"
                    )
                elif error:
                    lab.rosout.log("franka_control", "the error was recovered: the robot follows commands again")
                error = snapshot.error
            state = snapshot.trial.state
            if state != trial:
                if state == "succeeded":
                    lab.rosout.log(
                        "trial", f"trial of {snapshot.trial.participant} succeeded in {snapshot.trial.duration:.1f} s"
                    )
                elif state in ("failed", "abandoned"):
                    lab.rosout.log(
                        "trial", f"trial of {snapshot.trial.participant} {state}: {snapshot.trial.reason}", "WARN"
                    )
                elif state == "running":
                    lab.rosout.log("trial", f"trial of {snapshot.trial.participant} started")
                trial = state
            if lab.runtime.restarts != restarts:
                restarts = lab.runtime.restarts
                lab.rosout.log(node_name(LAB_NODE), f"the simulation restarted: {lab.runtime.last_death}", "ERROR")
