"""The 3D view (viser, same process as the API, bound to 127.0.0.1): the Panda with its meshes, the
plate, the box, the person's palm, F_ext split into its normal and tangential parts, the person's
force, a translucent friction cone, the box's path; and the lab's controls. The controls call the
same service registry and action server as the API (no second code path).

The scene is redrawn from the loop's snapshot at `rate_hz` inside `server.atomic()`. Light mode
draws the collision meshes (simple, few triangles) for software-rendered browsers.
"""

import hashlib
import math
import os
import threading
import time
from collections import deque
from contextlib import contextmanager
from http import HTTPStatus
from importlib.metadata import version
from pathlib import Path

import numpy as np
import pinocchio as pin
import viser
import websockets.asyncio.server

from sim.person.participants import PARTICIPANTS
from sim.recording.scene import ARROW_COLOURS, COLOURS, FORCE_SCALE, PALM_COLOUR, PLATE_COLOUR, arrows_of, state_of
from sim.robot.assets import mesh_cache, panda_urdf, robot_data_share
from sim.robot.panda import PandaModel
from sim.world import Snapshot

from app.api.security import host_refusal, local_names, origin_refusal
from app.lab import commands

NOT_SHOWN = ("panda_hand", "panda_leftfinger", "panda_rightfinger")  # the lab's EE is the plate, no gripper


@contextmanager
def guarded_websocket_server(bound_host: str):
    """While viser starts its server (it has no option for it), every HTTP request and WebSocket
    upgrade it gets passes the API's cross-site checks first: Host names this server, and an
    Origin, when sent, is the view's own page; else 403 (a forged gizmo message from another site
    never arrives)."""
    original = websockets.asyncio.server.serve
    names = local_names(bound_host)

    def serve(handler, *args, process_request=None, **kwargs):
        def check(connection, request):
            host = request.headers.get("Host")
            local = connection.local_address
            refusal = host_refusal(host, names, (local[0], local[1]) if local else None, "http")
            if refusal is None and request.headers.get("Upgrade", "").lower() == "websocket":
                refusal = origin_refusal(request.headers.get("Origin"), None, host)
            if refusal is not None:
                return connection.respond(HTTPStatus.FORBIDDEN, refusal + "\n")
            return process_request(connection, request) if process_request is not None else None

        return original(handler, *args, process_request=check, **kwargs)

    websockets.asyncio.server.serve = serve  # type: ignore[misc, assignment]  # wrapped while the view starts
    try:
        yield
    finally:
        websockets.asyncio.server.serve = original  # type: ignore[misc]


CAMERA_POSITION = (0.2, 1.6, 0.9)  # m, base frame: the robot and the box in view, from the person's side
CAMERA_LOOK_AT = (0.3, 0.1, 0.5)
CAMERA_FOV = math.radians(50.0)  # vertical; three.js' 75 degrees makes the lab small and distorted
PANEL_WIDTH = 300  # px: the controls docked at the right edge, beside the scene (never over it)
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


def wxyz(rotation: np.ndarray) -> np.ndarray:
    q = pin.Quaternion(np.asarray(rotation))
    return np.array([q.w, q.x, q.y, q.z])


def cone_mesh(mu: float, height: float = 0.08, segments: int = 24) -> tuple[np.ndarray, np.ndarray]:
    """Friction cone in the plate frame: apex at the centre, axis +z (into the box), half angle atan(mu)."""
    radius = height * mu
    angles = np.linspace(0.0, 2.0 * math.pi, segments, endpoint=False)
    ring = np.column_stack((radius * np.cos(angles), radius * np.sin(angles), np.full(segments, height)))
    vertices = np.vstack(([0.0, 0.0, 0.0], ring))
    faces = np.array([[0, 1 + i, 1 + (i + 1) % segments] for i in range(segments)])
    return vertices.astype(np.float32), faces.astype(np.int32)


def glb_of(mesh_path: Path, scale: tuple[float, ...]) -> bytes:
    """The mesh as GLB bytes for viser. Converting the Panda's .dae files with trimesh takes
    seconds, so the result is cached, keyed by the file (path, size, mtime), scale and trimesh version
    (trimesh itself, 0.7 s to import, is only imported to convert)."""

    stat = mesh_path.stat()
    key = hashlib.sha1(
        repr((str(mesh_path.resolve()), stat.st_size, stat.st_mtime_ns, scale, version("trimesh"))).encode()
    ).hexdigest()
    cached = mesh_cache() / f"{mesh_path.stem}-{key[:16]}.glb"
    try:
        return cached.read_bytes()
    except OSError:
        pass
    import trimesh

    mesh = trimesh.load(str(mesh_path), force="scene")
    mesh.apply_scale(np.asarray(scale))
    data = mesh.export(file_type="glb")  # type: ignore[call-arg]  # a scene's export: file_obj defaults to None
    try:  # best effort: a read-only home only costs the conversion next time
        cached.parent.mkdir(parents=True, exist_ok=True)
        partial = cached.with_suffix(f".{os.getpid()}.tmp")
        partial.write_bytes(data)
        partial.replace(cached)  # atomic: a concurrent start never reads half a file
    except OSError:
        pass
    return data


class SceneShapes:
    """The lab's shapes in a viser scene, as the live view and the replay draw them: the floor grid,
    the plate (a frame with its pad and friction cone), the box, the palm, the force arrows and the
    box's path. Sizes in m: plate (width, height), box (x, y, z), palm (x, y); mu is the cone's opening."""

    def __init__(self, scene, plate_size, box_size, palm_size, mu: float, box_colour) -> None:
        scene.add_grid("/floor", width=2.0, height=2.0, cell_size=0.1, position=(0.4, 0.2, 0.0))
        self.plate_frame = scene.add_frame("/plate", show_axes=False)
        scene.add_box(
            "/plate/pad", dimensions=(plate_size[0], plate_size[1], 0.006), color=PLATE_COLOUR, position=(0, 0, -0.003)
        )
        vertices, faces = cone_mesh(mu)
        self.cone = scene.add_mesh_simple(
            "/plate/friction_cone", vertices, faces, color=(255, 220, 0), opacity=0.3, side="double"
        )
        self.cone_mu = mu
        self.box = scene.add_box("/box", dimensions=tuple(box_size), color=box_colour)
        self.palm = scene.add_box("/palm", dimensions=(palm_size[0], palm_size[1], 0.015), color=PALM_COLOUR)
        self.arrows = {
            name: scene.add_arrows(
                f"/forces/{name}", np.zeros((1, 2, 3)), colour, shaft_radius=0.004, head_radius=0.01, head_length=0.02
            )
            for name, colour in ARROW_COLOURS.items()
        }
        self.path = scene.add_line_segments("/box_path", np.zeros((1, 2, 3)), colors=(120, 120, 120), thickness=0.004)

    def show_mu(self, mu: float) -> None:
        """Reshape the friction cone when mu changed."""
        if abs(mu - self.cone_mu) > 1e-9:
            self.cone.vertices = cone_mesh(mu)[0]
            self.cone_mu = mu


class RobotMeshes:
    """The Panda's meshes under viser frames, placed from q with pinocchio's geometry model."""

    def __init__(self, server: viser.ViserServer, light: bool) -> None:
        self.model = PandaModel()
        kind = pin.GeometryType.COLLISION if light else pin.GeometryType.VISUAL
        geometry = pin.buildGeomFromUrdf(
            self.model.model, str(panda_urdf()), kind, package_dirs=[str(robot_data_share())]
        )
        self.geometry = geometry
        self.geometry_data = pin.GeometryData(geometry)
        self.frames: list[tuple[int, viser.FrameHandle]] = []
        for index, obj in enumerate(geometry.geometryObjects):
            if obj.name.startswith(NOT_SHOWN) or not obj.meshPath.lower().endswith((".dae", ".stl", ".obj")):
                continue
            frame = server.scene.add_frame(f"/robot/{obj.name}", show_axes=False)
            server.scene.add_glb(
                f"/robot/{obj.name}/mesh",
                glb_of(Path(obj.meshPath), tuple(obj.meshScale)),
                cast_shadow=not light,
                receive_shadow=not light,
            )
            self.frames.append((index, frame))

    def place(self, q: np.ndarray) -> None:
        pin.framesForwardKinematics(self.model.model, self.model.data, q)
        pin.updateGeometryPlacements(self.model.model, self.model.data, self.geometry, self.geometry_data)
        for index, frame in self.frames:
            placement = self.geometry_data.oMg[index]
            frame.position = placement.translation
            frame.wxyz = wxyz(placement.rotation)


class SceneView:
    """A viser server drawing the lab: z up, the camera, default lights (none in light mode) and the
    Panda's meshes; a subclass draws the rest and has the thread's loop, `_run`, which runs from its
    start() until stop()."""

    def __init__(
        self, server: viser.ViserServer, light: bool, camera_position, camera_look_at, thread_name: str
    ) -> None:
        self.server = server
        server.scene.set_up_direction("+z")
        server.initial_camera.position = camera_position  # m, base frame
        server.initial_camera.look_at = camera_look_at
        server.initial_camera.fov = CAMERA_FOV
        server.gui.main_panel.dock_right()  # the canvas is what the panel leaves free
        server.gui.main_panel.set_width(PANEL_WIDTH)
        if light:
            server.scene.configure_default_lights(cast_shadow=False)
        self.robot = RobotMeshes(server, light)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name=thread_name, daemon=True)

    def _run(self) -> None:  # the subclass's loop
        raise NotImplementedError

    @property
    def url(self) -> str:
        return f"http://{self.server.get_host()}:{self.server.get_port()}"

    def stop(self) -> None:
        self._stop.set()
        self._thread.join(timeout=2.0)
        self.server.stop()


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
        with guarded_websocket_server(host):  # refuses foreign Host/Origin (app/api/security.py)
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

    def update(self, s: Snapshot) -> None:
        """Redraw everything that moves from one snapshot."""
        started = time.perf_counter()
        transform = s.transform_ee_to_base
        arrows = arrows_of(s, self.plate_offset)
        state = state_of(s)
        self._path.append(s.box_position.copy())
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
                self.update(self.lab.snapshot())
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
