"""The mobile world's 3D view (viser, as the lifting world's app/lab/view.py: same process as the
API, bound to the server's address, the same cross-site guard): the arena's walls, its obstacle, the
base (where it truly is), the latest scan's points (from where the base truly was when it was
taken) and the odometry's trail (where the odometry says the base went: it drifts from the truth).
Redrawn from the loop's snapshot at `rate_hz`. It only shows: the page's teleop drives the base."""

from __future__ import annotations

import math
import threading
from collections import deque
from typing import cast

import numpy as np
import viser

from sim.mobile.lidar import LidarSpec
from sim.mobile.playback import SCAN, MobilePlayback
from sim.mobile.recording import arena_description
from sim.mobile.world import MobileSnapshot

from app.view.replay import ReplayView
from app.view.scene import CAMERA_FOV, PANEL_WIDTH, guarded_websocket_server, watched

WALL_COLOUR, OBSTACLE_COLOUR, BASE_COLOUR = (150, 150, 160), (230, 160, 60), (60, 60, 70)
SCAN_COLOUR, TRAIL_COLOUR, CONTACT_COLOUR = (220, 30, 30), (40, 120, 220), (230, 40, 40)
BASE_HEIGHT = 0.143  # m, the Burger's stack (drawn)
TRAIL_POINTS = 2000  # odometry poses kept (one per period of the view's thread)


def yaw_wxyz(yaw: float) -> tuple[float, float, float, float]:
    return (math.cos(0.5 * yaw), 0.0, 0.0, math.sin(0.5 * yaw))


def scan_points(pose, ranges: np.ndarray, lidar: LidarSpec) -> np.ndarray:
    """The scan's returns (finite ranges) as points in the arena frame (m), at the scanner's height."""
    x, y, yaw = (float(v) for v in pose)
    c, s = math.cos(yaw), math.sin(yaw)
    sx, sy = x + c * lidar.offset_xy[0] - s * lidar.offset_xy[1], y + s * lidar.offset_xy[0] + c * lidar.offset_xy[1]
    angles = yaw + np.arange(len(ranges)) * lidar.angle_increment
    seen = np.isfinite(ranges)
    r = ranges[seen]
    return np.column_stack(
        (sx + r * np.cos(angles[seen]), sy + r * np.sin(angles[seen]), np.full(r.shape, lidar.height))
    )


class MobileScene:
    """The arena, the base, the scan's points and the odometry's trail in a viser scene, drawn from
    an arena's description (sim/mobile/recording.py `arena_description`: live and recorded alike)."""

    def __init__(self, server: viser.ViserServer, arena: dict, light: bool) -> None:
        self.server = server
        server.scene.set_up_direction("+z")
        server.initial_camera.position = (0.0, -4.5, 4.0)  # m, arena frame
        server.initial_camera.look_at = (0.0, 0.0, 0.0)
        server.initial_camera.fov = CAMERA_FOV
        server.gui.main_panel.dock_right()
        server.gui.main_panel.set_width(PANEL_WIDTH)
        if light:
            server.scene.configure_default_lights(cast_shadow=False)
        self.lidar = LidarSpec()
        self._draw_arena(arena)
        scene = server.scene
        self.base = scene.add_frame("/base_footprint", show_axes=False)
        radius = arena["footprint_radius"]
        self.body = scene.add_cylinder(
            "/base_footprint/body",
            radius=radius,
            height=BASE_HEIGHT,
            color=BASE_COLOUR,
            position=(0, 0, BASE_HEIGHT / 2),
        )
        scene.add_box(
            "/base_footprint/front",
            dimensions=(0.06, 0.02, 0.01),
            color=(250, 250, 250),
            position=(radius - 0.03, 0, BASE_HEIGHT + 0.005),
        )
        self.scan = scene.add_point_cloud("/scan", np.zeros((1, 3)), SCAN_COLOUR, point_size=0.03, point_shape="circle")
        self.trail = scene.add_line_segments("/odom_trail", np.zeros((1, 2, 3)), colors=TRAIL_COLOUR, thickness=2.0)

    def _draw_arena(self, arena: dict) -> None:
        scene = self.server.scene
        hx, hy = arena["half_size_xy"]
        t, h = arena["wall_thickness"], arena["wall_height"]
        scene.add_grid("/floor", width=2 * hx, height=2 * hy, cell_size=0.25)
        for name, size, centre in (
            ("east", (t, 2 * hy + 2 * t, h), (hx + t / 2, 0.0)),
            ("west", (t, 2 * hy + 2 * t, h), (-hx - t / 2, 0.0)),
            ("north", (2 * hx, t, h), (0.0, hy + t / 2)),
            ("south", (2 * hx, t, h), (0.0, -hy - t / 2)),
        ):
            scene.add_box(f"/arena/{name}", dimensions=size, color=WALL_COLOUR, position=(centre[0], centre[1], h / 2))
        for i, obstacle in enumerate(arena["obstacles"]):
            (cx, cy), size_ = obstacle["center_xy"], obstacle["size"]
            if obstacle["shape"] == "cylinder":
                scene.add_cylinder(
                    f"/arena/obstacle_{i}", radius=size_[0], height=h, color=OBSTACLE_COLOUR, position=(cx, cy, h / 2)
                )
            else:
                scene.add_box(
                    f"/arena/obstacle_{i}",
                    dimensions=(2 * size_[0], 2 * size_[1], h),
                    color=OBSTACLE_COLOUR,
                    position=(cx, cy, h / 2),
                    wxyz=yaw_wxyz(obstacle["yaw"]),
                )

    def draw(self, pose, contact: bool, scan: np.ndarray | None, trail_xy: np.ndarray) -> None:
        """The base at its true pose; the scan's points when given (`scan`: [x, y, z] rows, arena
        frame); the odometry's trail."""
        x, y, yaw = (float(v) for v in pose)
        with self.server.atomic():
            self.base.position = (x, y, 0.0)
            self.base.wxyz = yaw_wxyz(yaw)
            self.body.color = CONTACT_COLOUR if contact else BASE_COLOUR
            if scan is not None:
                self.scan.points = (scan if len(scan) else np.zeros((1, 3))).astype(np.float32)
            if len(trail_xy) >= 2:
                line = np.hstack((trail_xy, np.full((len(trail_xy), 1), 0.005)))
                self.trail.points = np.stack((line[:-1], line[1:]), axis=1)


class MobileView:
    """The live view: the scene redrawn from the lab's snapshots while a browser looks (`watched`)."""

    def __init__(
        self, lab, host: str = "127.0.0.1", port: int = 8080, light: bool = False, rate_hz: float = 20.0
    ) -> None:
        self.lab, self.light, self.rate_hz = lab, light, rate_hz
        with guarded_websocket_server(host):  # refuses foreign Host/Origin (app/security.py)
            self.server = viser.ViserServer(host=host, port=port, verbose=False)
        self.scene = MobileScene(self.server, arena_description(lab.world.config), light)
        self.lidar: LidarSpec = lab.world.config.lidar
        self.status = self.server.gui.add_markdown("")
        self._trail: deque[tuple[float, float]] = deque(maxlen=TRAIL_POINTS)
        self._scan_time = -1.0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="mobile-view", daemon=True)

    @property
    def url(self) -> str:
        return f"http://{self.server.get_host()}:{self.server.get_port()}"

    def start(self) -> None:
        self.update(self.lab.snapshot())
        self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        self._thread.join(timeout=2.0)
        self.server.stop()

    def record(self, s: MobileSnapshot) -> None:
        """Keep what the view accumulates whoever looks: the odometry's trail."""
        self._trail.append((float(s.odom_pose[0]), float(s.odom_pose[1])))

    def update(self, s: MobileSnapshot) -> None:
        """Record, then redraw from one snapshot."""
        self.record(s)
        scan = None
        if s.scan_time != self._scan_time:
            self._scan_time = s.scan_time
            scan = scan_points(s.pose, s.scan_ranges, self.lidar)
        self.scene.draw(s.pose, s.contact, scan, np.array(self._trail))
        w = s.wall
        self.status.content = (
            f"**t** {s.time:.1f} s · **v** {s.velocity[0]:.2f} m/s · **w** {s.velocity[1]:.2f} rad/s  \n"
            f"obstacle {w.distance:.2f} m · around it {math.degrees(w.circuit):.0f} deg"
            + (f"  \n**contact** with {s.contact_with}" if s.contact else "")
        )

    def _run(self) -> None:
        period = 1.0 / self.rate_hz
        while not self._stop.wait(period):
            try:
                snapshot = self.lab.snapshot()
                if watched(self.server):
                    self.update(snapshot)
                else:
                    self.record(snapshot)
            except Exception:  # noqa: BLE001 - a drawing problem never stops the lab
                pass


class MobileReplayView(ReplayView):
    """`hri-lab play` of a mobile world's recording: the scene at the playback time (the base's true
    pose, the last scan, the odometry's trail so far), with the replay's slider, play, pause and
    speed (app/view/replay.py's controls and its read-only topics API)."""

    def __init__(
        self,
        playback: MobilePlayback,
        host: str = "127.0.0.1",
        port: int = 8080,
        light: bool = False,
        rate_hz: float = 30.0,
    ) -> None:
        self.playback = playback  # type: ignore[assignment]  # the replay's controls need its times, duration, path
        self.rate_hz, self.light = rate_hz, light
        self.time, self.playing, self.speed = 0.0, False, 1.0
        with guarded_websocket_server(host):
            self.server = viser.ViserServer(host=host, port=port, verbose=False)
        self.scene = MobileScene(self.server, playback.world, light)
        self.lidar = LidarSpec()
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="mobile-replay", daemon=True)
        self._build_gui()

    def draw(self, t: float) -> None:
        playback = cast(MobilePlayback, self.playback)
        pose = playback.pose_at(t)
        scan = playback.message_at(SCAN, t) if SCAN in playback.topics else None
        points = None
        if scan is not None:  # from where the base truly was when the scan was taken
            taken = scan["timestamp"]["sec"] + scan["timestamp"]["nsec"] * 1e-9 - playback.start / 1e9
            ranges = np.array([math.inf if r is None else r for r in scan["ranges"]])
            points = scan_points(playback.pose_at(taken), ranges, self.lidar)
        wall = playback.message_at("/wall_following", t) if "/wall_following" in playback.topics else None
        self.scene.draw(pose, bool(wall and wall["contact"]), points, playback.trail_until(t))
        self.status.content = f"t = {t:.2f} / {playback.duration:.2f} s" + (
            f" · obstacle {wall['distance']:.2f} m · around it {abs(wall['circuit_deg']):.0f} deg" if wall else ""
        )
