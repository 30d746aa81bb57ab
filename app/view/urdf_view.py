"""`hri-lab urdf view FILE.urdf`: a student's URDF in a 3D view (viser's `ViserUrdf`) with a slider
per movable joint, as RViz with joint_state_publisher_gui shows it.

The sliders are joint_state_publisher_gui's: one per movable joint that is not a mimic (yourdfpy's
actuated joints), its range the file's `<limit>` (a continuous joint's is ±pi), starting at 0, or
at the middle of the range when 0 is outside it; "Centre" puts them back. "Show frames" draws each
link's frame (x red, y green, z blue). `JointStates` holds the sliders' values as the
`sensor_msgs/JointState` joint_state_publisher publishes (positions in rad, or m for a prismatic
joint); app/view/urdf_bridge.py serves it over rosbridge and HTTP.
"""

from __future__ import annotations

import math
import threading
import time
from functools import partial
from pathlib import Path

import numpy as np
import viser

from sim.robot.urdf_check import UrdfModel

from app.view.scene import PANEL_WIDTH, guarded_websocket_server, wxyz

FRAME_AXES_LENGTH_M = 0.05
SLIDER_STEPS = 1000  # a slider's range in this many steps


def start_position(low: float, high: float) -> float:
    """joint_state_publisher's first value: 0 when the range holds it, else the range's middle."""
    return 0.0 if low <= 0.0 <= high else (low + high) / 2.0


class JointStates:
    """The sliders' joint positions, thread-safe (viser's callbacks and the bridge's event loop)."""

    def __init__(self, names: list[str], positions: list[float]) -> None:
        self.names = list(names)
        self._positions = dict(zip(names, (float(p) for p in positions)))
        self._lock = threading.Lock()
        self.version = 0  # counts the changes (the bridge sends a change at once)

    def set(self, name: str, position: float) -> None:
        with self._lock:
            self._positions[name] = float(position)
            self.version += 1

    def position(self, name: str) -> float:
        with self._lock:
            return self._positions[name]

    def positions(self) -> list[float]:
        with self._lock:
            return [self._positions[n] for n in self.names]

    def message(self) -> dict:
        """sensor_msgs/JointState now (stamp: the wall clock, as joint_state_publisher's)."""
        now = time.time()
        sec = int(now)
        return {
            "header": {"stamp": {"sec": sec, "nanosec": int((now - sec) * 1e9)}, "frame_id": ""},
            "name": list(self.names),
            "position": self.positions(),
            "velocity": [],
            "effort": [],
        }


class UrdfView:
    """The 3D view of one URDF (a file `parse_urdf_file` accepted) on viser's own port."""

    def __init__(self, path: Path, model: UrdfModel, host: str = "127.0.0.1", port: int = 8080) -> None:
        import yourdfpy
        from viser.extras import ViserUrdf

        self.path, self.model, self.host = Path(path), model, host
        self.urdf = yourdfpy.URDF.load(
            str(self.path),
            build_scene_graph=True,
            load_meshes=True,
            build_collision_scene_graph=False,
            load_collision_meshes=False,
            filename_handler=partial(yourdfpy.filename_handler_magic, dir=self.path.parent),
        )
        with guarded_websocket_server(host):  # refuses foreign Host/Origin, as the lab's views do
            self.server = viser.ViserServer(host=host, port=port, verbose=False)
        self.server.gui.main_panel.dock_right()  # the sliders beside the robot, as the lab's view has them
        self.server.gui.main_panel.set_width(PANEL_WIDTH)
        self.server.scene.add_grid("/grid", width=2.0, height=2.0, cell_size=0.1)
        self.robot = ViserUrdf(self.server, self.urdf, root_node_name="/robot")
        joints = {j.name: j for j in model.joints}
        names = [str(n) for n in self.urdf.actuated_joint_names]
        self.ranges = {name: joints[name].slider_range() for name in names}
        self.start = {name: start_position(*self.ranges[name]) for name in names}
        self.states = JointStates(names, [self.start[n] for n in names])
        self._build_gui(names)
        self._frames = {
            link.name: self.server.scene.add_frame(
                f"/frames/{link.name}", axes_length=FRAME_AXES_LENGTH_M, axes_radius=0.003, visible=False
            )
            for link in model.links
        }
        self._update()

    @property
    def url(self) -> str:
        return f"http://{self.host}:{self.server.get_port()}"

    def _build_gui(self, names: list[str]) -> None:
        gui = self.server.gui
        gui.add_markdown(f"**{self.model.name}** — `{self.path.name}`")
        self.sliders: dict[str, viser.GuiInputHandle[float]] = {}
        with gui.add_folder("Joints"):
            for name in names:
                low, high = self.ranges[name]
                slider: viser.GuiInputHandle[float]
                if high > low:
                    slider = gui.add_slider(
                        name, min=low, max=high, step=(high - low) / SLIDER_STEPS, initial_value=self.start[name]
                    )
                else:  # lower == upper: nothing to move, shown as joint_state_publisher_gui shows it
                    slider = gui.add_number(name, initial_value=low, disabled=True)
                slider.on_update(partial(self._moved, name))
                self.sliders[name] = slider
        centre = gui.add_button("Centre")
        centre.on_click(lambda _: self.centre())
        self.show_frames = gui.add_checkbox("Show frames", initial_value=False)
        self.show_frames.on_update(lambda _: self._update())

    def _moved(self, name: str, event) -> None:
        """A slider moved: its value, kept in the joint's range (a page can send any number)."""
        low, high = self.ranges[name]
        value = float(event.target.value)
        kept = min(max(value, low), high) if math.isfinite(value) else self.states.position(name)
        if kept != value:
            self.sliders[name].value = kept  # type: ignore[misc]  # calls back with the kept value; viser 1.1.1 defines the setter apart from its getter: mypy reads it as read-only
            return
        self.states.set(name, kept)
        self._update()

    def centre(self) -> None:
        for name, slider in self.sliders.items():
            slider.value = self.start[name]  # type: ignore[misc]  # as above

    def _update(self) -> None:
        """The robot (and the frames, when shown) at the sliders' positions."""
        self.robot.update_cfg(np.array(self.states.positions(), dtype=float))
        shown = bool(self.show_frames.value)
        with self.server.atomic():
            for link, frame in self._frames.items():
                frame.visible = shown
                if shown:
                    transform_link_to_base = self.urdf.get_transform(link)
                    frame.position = transform_link_to_base[:3, 3]
                    frame.wxyz = wxyz(transform_link_to_base[:3, :3])

    def stop(self) -> None:
        self.server.stop()
