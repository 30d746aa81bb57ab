"""The 3D view (viser, same process as the API, bound to 127.0.0.1): the Panda with its meshes, the
plate, the box, the person's palm, F_ext split into its normal and tangential parts, the person's
force, a translucent friction cone, the box's path; and the lab's controls. The controls call the
same service registry and action server as the API (no second code path).

The scene is redrawn from the loop's snapshot at `rate_hz` inside `server.atomic()` while a browser
looks (`watched`); the box's path is kept whoever looks. Light mode
draws the collision meshes (simple, few triangles) for software-rendered browsers.
"""

import time
from collections import deque

import numpy as np
import viser

from sim.person.participants import PARTICIPANTS
from sim.recording.scene import ARROW_COLOURS, COLOURS, FORCE_SCALE, arrows_of, state_of
from sim.world import Snapshot

from app.lab import commands
from app.view.scene import SceneShapes, SceneView, guarded_websocket_server, watched, wxyz

CAMERA_POSITION = (0.2, 1.6, 0.9)  # m, base frame: the robot and the box in view, from the person's side
CAMERA_LOOK_AT = (0.3, 0.1, 0.5)
GIZMO_SIZE = 90  # px on screen whatever the zoom (arrows from the palm), drawn over the box
MEANING = {  # state -> what the box colour says (the view's legend)
    "inside": "f_n inside the band",
    "below": "f_n below the band",
    "above": "f_n above the band",
    "slipping": "the plate slips on the box",
    "error": "robot reflex (error)",
    "idle": "lifting stopped",
}
ARROWS = {  # arrow -> (RGB, what it shows)
    "normal": (ARROW_COLOURS["normal"], "F_ext, normal part (at the plate)"),
    "tangential": (ARROW_COLOURS["tangential"], "F_ext, tangential part"),
    "human": (ARROW_COLOURS["human"], "the person's push (at the palm)"),
}


def legend_markdown() -> str:
    """The legend of the box colours, the arrows and the other shapes (HTML swatches in markdown)."""

    def swatch(rgb):
        return f'<span style="display:inline-block;width:0.9em;height:0.9em;background:rgb{tuple(rgb)}"></span>'

    boxes = "<br>".join(f"{swatch(COLOURS[k])} {text}" for k, text in MEANING.items())
    arrows = "<br>".join(f"{swatch(rgb)} {text}" for rgb, text in ARROWS.values())
    return (
        f"**Box colour**<br>{boxes}<br><br>**Arrows** ({FORCE_SCALE * 100:g} cm per N)<br>{arrows}<br><br>"
        f"{swatch((255, 220, 0))} friction cone (opening = mu)<br>{swatch((120, 120, 120))} the box's path"
    )


class LabView(SceneView):
    def __init__(
        self,
        lab,
        actions,
        services,
        host: str = "127.0.0.1",
        port: int = 8080,
        light: bool = False,
        rate_hz: float = 30.0,
        controls: bool = True,
    ) -> None:
        self.lab, self.actions, self.services = lab, actions, services
        self.light = light
        self.rate_hz = rate_hz
        with guarded_websocket_server(host):  # refuses foreign Host/Origin (app/security.py)
            server = viser.ViserServer(host=host, port=port, verbose=False)
        super().__init__(server, light, CAMERA_POSITION, CAMERA_LOOK_AT, "view3d")
        self.controls = controls  # off when the API needs a token: the view then only shows
        self._build_scene()
        self._build_gui()
        self.server.gui.main_panel.minimize()  # the page embeds this view: the scene first, the controls one click away
        self.status_message = ""  # the answer to the last control used here
        self.frame_times: deque[float] = deque(maxlen=1000)
        self._path: deque[np.ndarray] = deque(maxlen=300)

    def start(self) -> None:
        self.update(self.lab.snapshot())
        self._thread.start()

    # --- scene ------------------------------------------------------------------------------
    def _build_scene(self) -> None:
        scene = self.server.scene
        s = self.lab.snapshot()
        geometry = self.lab.call(commands.scene_geometry)
        plate_width, plate_height, self.plate_offset = geometry["plate"]
        self.shapes = SceneShapes(
            scene, (plate_width, plate_height), geometry["box"], geometry["palm"], s.lifting.mu, COLOURS["idle"]
        )
        self.gizmo = scene.add_transform_controls(
            "/hand_target",
            scale=GIZMO_SIZE,
            fixed=True,
            line_width=4.0,
            depth_test=False,
            disable_rotations=True,
            disable_sliders=True,
            position=s.palm_position,
            visible=self.controls,
        )
        if self.controls:
            self.gizmo.on_update(self._on_gizmo)

    def record(self, s: Snapshot) -> None:
        """Keep what the view accumulates whoever looks: the box's path."""
        self._path.append(s.box_position.copy())

    def update(self, s: Snapshot) -> None:
        """Record, then redraw everything that moves from one snapshot."""
        started = time.perf_counter()
        self.record(s)
        transform = s.transform_ee_to_base
        arrows = arrows_of(s, self.plate_offset)
        state = state_of(s)
        shapes = self.shapes
        with self.server.atomic():
            self.robot.place(s.q)
            shapes.plate_frame.position = transform[:3, 3] + transform[:3, 2] * self.plate_offset
            shapes.plate_frame.wxyz = wxyz(transform[:3, :3])
            shapes.box.position = s.box_position
            shapes.box.wxyz = wxyz(s.box_rotation)
            shapes.box.color = COLOURS[state]
            shapes.palm.position = s.palm_position
            shapes.palm.wxyz = wxyz(s.palm_rotation)
            if s.human_phase != "manual":  # the gizmo rides on the palm until the palm is taken over
                self.gizmo.position = s.palm_position
            for name, handle in shapes.arrows.items():
                handle.points = arrows[name][None]
            shapes.show_mu(s.lifting.mu)
            if len(self._path) >= 2 and len(self._path) % 5 == 0:
                points = np.array(self._path)
                shapes.path.points = np.stack((points[:-1], points[1:]), axis=1)
        self._update_gui(s, state)
        self.frame_times.append(time.perf_counter() - started)

    def _run(self) -> None:
        period = 1.0 / self.rate_hz
        while not self._stop.wait(period):
            try:
                snapshot = self.lab.snapshot()
                if watched(self.server):
                    self.update(snapshot)
                else:
                    self.record(snapshot)
            except Exception as exc:  # noqa: BLE001 - a drawing problem never stops the lab
                self.status_message = f"view error: {exc}"

    # --- controls -----------------------------------------------------------------------------
    def _build_gui(self) -> None:
        gui = self.server.gui
        gui.add_markdown("**hri-lab** — cooperative lifting (plots, results and the API: the dashboard page)")
        self.status = gui.add_markdown("")
        if self.controls:
            self._build_controls()
        with gui.add_folder("Legend", expand_by_default=True):
            gui.add_markdown(legend_markdown())

    def _build_controls(self) -> None:
        gui = self.server.gui
        with gui.add_folder("Lifting"):
            self.force = gui.add_number("Force (N)", initial_value=10.0, min=0.0, max=60.0, step=0.5)
            gui.add_button("Start lifting").on_click(
                lambda _: self._call("/start_cooperative_lifting", force=float(self.force.value))
            )
            gui.add_button("Stop lifting").on_click(lambda _: self._call("/stop_cooperative_lifting"))
            gui.add_button("Move to start").on_click(lambda _: self._move_to_start())
            gui.add_button("Reset").on_click(lambda _: self._call("/reset_simulation"))
            gui.add_button("Error recovery").on_click(lambda _: self._call("/error_recovery"))
        with gui.add_folder("Person"):
            self.participant = gui.add_dropdown("Participant", tuple(PARTICIPANTS), initial_value="calm")
            gui.add_button("Run scripted participant").on_click(lambda _: self._run_participant())
            self.take_over = gui.add_checkbox(
                "Take over the palm",
                initial_value=False,
                hint="The scripted person stops; drag the gizmo to move the palm. Uncheck: Reset.",
            )
            self.take_over.on_update(self._on_take_over)
            gui.add_markdown("Take over, then drag the gizmo on the palm to lift and carry the box yourself.")

    def _update_gui(self, s: Snapshot, state: str) -> None:
        """The status line, from the snapshot only: current whoever changed the state."""
        lifting = (
            f"lifting **on**, band [{s.lifting.f_n_min:g}, {s.lifting.f_n_max:g}] N"
            if s.lifting.running
            else "lifting **off**"
        )
        trial = s.trial
        result = {
            "running": f"trial running ({trial.duration:.1f} s)",
            "succeeded": f"trial **succeeded** in {trial.duration:.1f} s, slip {trial.slip * 1e3:.1f} mm",
            "failed": f"trial **failed**: {trial.reason}",
            "abandoned": "trial abandoned (palm taken over)",
        }.get(trial.state, "")
        lines = [
            f"{lifting} · f_n = {s.plate.normal_force:.1f} N · box: {MEANING[state]}",
            f"person: {s.human_phase}" + (f" · {result}" if result else ""),
        ]
        if s.error:
            lines.append(f"**reflex:** {s.error.splitlines()[0]} (Error recovery clears it)")
        if self.status_message:
            lines.append(f"last command: {self.status_message}")
        content = "\n\n".join(lines)
        if content != self.status.content:
            self.status.content = content
        if self.controls and self.take_over.value != (s.human_phase == "manual"):
            self._syncing = True
            self.take_over.value = s.human_phase == "manual"  # type: ignore[misc]  # viser's handles take a value
            self._syncing = False

    def _call(self, name: str, **request) -> None:
        """A service of the registry, exactly as POST /services{name} calls it."""
        try:
            response = self.services.call(self.lab, name, self.services.get(name).request(**request)).model_dump()
            self.status_message = f"{name}: {response.get('message', 'done')}" + (
                "" if response.get("success", True) else " (failed)"
            )
        except Exception as exc:  # noqa: BLE001 - shown to the person, the view goes on
            self.status_message = f"{name} failed: {exc}"

    def _move_to_start(self) -> None:
        action = self.actions.get("/move_to_start")
        handle = self.actions.send_goal(action, action.goal())
        self.status_message = f"/move_to_start: goal {handle.status.value}" + (
            f" ({handle.message})" if handle.message else ""
        )

    def _run_participant(self) -> None:
        try:
            self.lab.params.set("human", "profile", self.participant.value)
        except Exception as exc:  # noqa: BLE001 - any refusal is the panel's message, never the view's end
            self.status_message = f"participant refused: {exc}"
            return
        self._call("/reset_simulation")
        self._call("/start_cooperative_lifting", force=float(self.force.value))
        self.gizmo.position = self.lab.snapshot().palm_position

    def _on_take_over(self, _event) -> None:
        """Checked: the palm is the user's (the scripted person stops where it is); unchecked: Reset."""
        if getattr(self, "_syncing", False):
            return
        if self.take_over.value:
            palm = self.lab.snapshot().palm_position
            self.gizmo.position = palm
            self._set_hand(palm)
            self.status_message = "the palm is yours: drag the gizmo (Reset gives it back to the scripted person)"
        else:
            self._call("/reset_simulation")

    def _set_hand(self, target: np.ndarray) -> None:
        try:
            self.lab.call(commands.set_hand_target, np.asarray(target, dtype=float))
        except Exception as exc:  # noqa: BLE001 - a restarting simulation or a refused target: said in the panel
            self.status_message = f"hand target refused: {exc}"

    def _on_gizmo(self, _event) -> None:
        self._set_hand(np.array(self.gizmo.position, dtype=float))  # dragging takes the palm over too
