"""What every 3D view of the lab is built from (the live view, app/lab/view.py; the replay,
replay.py; the mobile world's, mobile_view.py; a student's URDF, urdf_view.py): a viser server
started behind the cross-site checks (`guarded_websocket_server`, app/security.py's), the camera's
field of view and the docked panel's width, rotations as viser's wxyz, the lab's shapes
(`SceneShapes`: plate, friction cone, box, palm, arrows, the box's path), the Panda and `SceneView`,
the base of a view that draws the lab with its own thread. A view imports these, never another view.
"""

from __future__ import annotations

import hashlib
import math
import os
import threading
from contextlib import contextmanager
from http import HTTPStatus
from importlib.metadata import version
from pathlib import Path

import numpy as np
import pinocchio as pin
import viser
import websockets.asyncio.server

from sim.recording.scene import ARROW_COLOURS, PALM_COLOUR, PLATE_COLOUR
from sim.robot.assets import mesh_cache, panda_urdf, robot_data_share
from sim.robot.panda import PandaModel

from app.security import PROXY_HEADER, host_refusal, local_names, origin_refusal, proxy_refusal, proxy_secret

NOT_SHOWN = ("panda_hand", "panda_leftfinger", "panda_rightfinger")  # the lab's EE is the plate, no gripper

CAMERA_FOV = math.radians(50.0)  # vertical; three.js' 75 degrees makes the lab small and distorted
PANEL_WIDTH = 300  # px: the controls docked at the right edge, beside the scene (never over it)


@contextmanager
def guarded_websocket_server(bound_host: str):
    """While viser starts its server (it has no option for it), every HTTP request and WebSocket
    upgrade it gets passes the API's cross-site checks first: Host names this server, and an
    Origin, when sent, is the view's own page; else 403 (a forged gizmo message from another site
    never arrives). Behind a JupyterHub, only what the lab's own relay sends (app/api/view_relay.py:
    the proxy's secret, app/security.py)."""
    original = websockets.asyncio.server.serve
    names = local_names(bound_host)
    secret = proxy_secret()

    def serve(handler, *args, process_request=None, **kwargs):
        def check(connection, request):
            host = request.headers.get("Host")
            local = connection.local_address
            if secret:
                refusal = proxy_refusal(request.headers.get(PROXY_HEADER), secret)
            else:
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


def watched(server: viser.ViserServer) -> bool:
    """A browser has this view open. A live view draws only then: nobody looking, it keeps what it
    accumulates (the box's path, the odometry's trail) and draws nothing, so an idle lab whose view
    nobody opened spends no CPU on frames (`python -m bench.idle_cpu --view full`). A browser that
    connects is sent the scene as last drawn; the next frame (1/rate_hz later) brings it up to date."""
    return bool(server.get_clients())


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
