"""`hri-lab play FILE.mcap`: a recording in the 3D view (viser) with a time slider — play, pause,
speed, scrub — drawn like the live view (the Panda's meshes from the recorded q, the plate with
its friction cone, the box in its state colour, the palm, the same force arrows and colours, the
box's path), and the recorded topics served read-only like `ros2 bag play` publishes them:

  GET /topics                    the recorded topics with their types
  GET /topics/NAME               the message of NAME at the playback time (the last one recorded at or before it)
  WS  /topics/NAME/stream?rate=  the messages as the playback passes them (at most `rate` a second)
  GET /replay                    file, duration, playback time, playing, speed, the 3D view's URL

so `hri-lab topic echo NAME --url URL` reads a recording as it reads the live lab.
"""

from __future__ import annotations

import asyncio
import base64
import threading
import time

import cv2
import numpy as np
import viser
from fastapi import FastAPI, HTTPException, Query, WebSocket, WebSocketDisconnect

from sim.recording.playback import Playback
from sim.recording.writer import IMAGE_TOPIC

from app.view.scene import SceneShapes, SceneView, guarded_websocket_server, wxyz

SPEEDS = ("0.25", "0.5", "1", "2", "4")


class ReplayView(SceneView):
    def __init__(
        self, playback: Playback, host: str = "127.0.0.1", port: int = 8080, light: bool = False, rate_hz: float = 30.0
    ) -> None:
        self.playback = playback
        self.rate_hz = rate_hz
        self.time = 0.0  # s, playback time
        self.playing = False
        self.speed = 1.0
        with guarded_websocket_server(host):  # refuses foreign Host/Origin, as the live view does
            server = viser.ViserServer(host=host, port=port, verbose=False)
        super().__init__(server, light, (1.6, 1.5, 1.0), (0.45, 0.2, 0.35), "replay")
        self._lock = threading.Lock()
        self._build_scene()
        self._build_gui()

    def start(self) -> None:
        self.seek(0.0)
        self._thread.start()

    # --- scene ------------------------------------------------------------------------------
    def _build_scene(self) -> None:
        scene, world = self.server.scene, self.playback.world
        plate = world.get("plate", {"width": 0.1, "height": 0.1, "offset": 0.02})
        first = self.playback.frames[0]
        self.shapes = SceneShapes(
            scene,
            (plate["width"], plate["height"]),
            world.get("box_size", (0.2, 0.2, 0.2)),
            world.get("palm_size", (0.08, 0.08)),
            first.mu,
            first.box_colour,
        )
        self.box_path = np.array([f.poses["box"][0] for f in self.playback.frames])
        self.camera: viser.GuiImageHandle | None = None  # the recorded camera image (live recordings), in the panel
        self._shown_image = None

    def draw(self, t: float) -> None:
        """Show the recording at playback time t (s)."""
        frame = self.playback.frame_at(t)
        with self.server.atomic():
            self.robot.place(frame.q)
            shapes = self.shapes
            for handle, name in ((shapes.plate_frame, "plate"), (shapes.box, "box"), (shapes.palm, "palm")):
                position, rotation = frame.poses[name]
                handle.position = position
                handle.wxyz = wxyz(rotation)
            shapes.box.color = frame.box_colour
            for name, handle in shapes.arrows.items():
                handle.points = frame.arrows[name][None]
            shapes.show_mu(frame.mu)
            shown = self.box_path[
                max(0, int(np.searchsorted(self.playback.times, t, side="right")) - 300) : int(
                    np.searchsorted(self.playback.times, t, side="right")
                )
            ]
            if len(shown) >= 2:
                shapes.path.points = np.stack((shown[:-1], shown[1:]), axis=1)
        self._show_image(frame.time)
        contact = self.playback.message_at("/contact_state", frame.time) or {}
        lifting = self.playback.message_at("/lifting_state", frame.time) or {}
        band = (
            f"band [{lifting.get('f_n_min', 0):g}, {lifting.get('f_n_max', 0):g}] N"
            if lifting.get("started")
            else "lifting stopped"
        )
        self.status.content = (
            f"t = {frame.time:.2f} / {self.playback.duration:.2f} s · `{frame.state}` · {band} · "
            f"f_n = {contact.get('normal_force', 0.0):.1f} N · person: {lifting.get('human_phase', '')}"
            + (f"\n\n**reflex:** {lifting['error']}" if lifting.get("error") else "")
        )

    def _show_image(self, t: float) -> None:
        """The camera's recorded image at t (s), when the recording has images."""
        if IMAGE_TOPIC not in self.playback.topics:
            return
        message = self.playback.message_at(IMAGE_TOPIC, t)
        if message is None or message["data"] == self._shown_image:
            return
        self._shown_image = message["data"]
        bgr = cv2.imdecode(np.frombuffer(base64.b64decode(message["data"]), np.uint8), cv2.IMREAD_COLOR)
        if bgr is None:
            return
        if self.camera is None:
            self.camera = self.server.gui.add_image(bgr[:, :, ::-1], label="camera (/image_raw)", format="jpeg")
        else:
            self.camera.image = bgr[:, :, ::-1]

    def seek(self, t: float) -> None:
        """Scrub to t (s): the slider, the scene."""
        with self._lock:
            self.time = min(max(0.0, t), self.playback.duration)
            self._setting = True
            try:
                self.slider.value = round(self.time, 3)  # type: ignore[misc]  # viser's handles take a value
            finally:
                self._setting = False
        self.draw(self.time)

    # --- controls ---------------------------------------------------------------------------
    def _build_gui(self) -> None:
        gui = self.server.gui
        gui.add_markdown(f"**hri-lab replay** — `{self.playback.path.name}`")
        self.status = gui.add_markdown("")
        self._setting = False
        step = max(0.001, float(np.min(np.diff(self.playback.times)))) if len(self.playback.times) > 1 else 0.04
        self.slider = gui.add_slider(
            "Time (s)", min=0.0, max=max(self.playback.duration, step), step=step, initial_value=0.0
        )
        self.slider.on_update(self._on_slider)
        self.play_button = gui.add_button("Play")
        self.play_button.on_click(lambda _: self.play())
        gui.add_button("Pause").on_click(lambda _: self.pause())
        self.speed_menu = gui.add_dropdown("Speed", SPEEDS, initial_value="1")
        self.speed_menu.on_update(lambda _: setattr(self, "speed", float(self.speed_menu.value)))

    def _on_slider(self, _event) -> None:
        if not self._setting:  # a person dragged it
            self.time = float(self.slider.value)
            self.draw(self.time)

    def play(self) -> None:
        if self.time >= self.playback.duration:
            self.seek(0.0)
        self.playing = True

    def pause(self) -> None:
        self.playing = False

    def _run(self) -> None:
        period = 1.0 / self.rate_hz
        last = time.monotonic()
        while not self._stop.wait(period):
            now = time.monotonic()
            if self.playing:
                t = self.time + (now - last) * self.speed
                if t >= self.playback.duration:
                    t, self.playing = self.playback.duration, False
                try:
                    self.seek(t)
                except Exception:  # noqa: BLE001 - a drawing problem never stops the player
                    pass
            last = now


def replay_app(view: ReplayView) -> FastAPI:
    """The read-only API of a replay: the recorded topics at the playback time."""
    playback = view.playback
    app = FastAPI(title="hri-lab replay", description=f"Replay of {playback.path.name}: the recorded topics.")

    def topic_of(name: str) -> str:
        topic = "/" + name.lstrip("/")
        if topic not in playback.topics:
            raise HTTPException(404, f"topic '{topic}' was not recorded")
        return topic

    @app.get("/topics", summary="The recorded topics with their types (ros2 topic list -t)")
    def topics() -> list[dict]:
        return [{"name": name, "type": kind} for name, (kind, _, _) in playback.topics.items()]

    @app.get("/topics/{name:path}", summary="The message of a topic at the playback time")
    def latest(name: str) -> dict:
        message = playback.message_at(topic_of(name), view.time)
        if message is None:
            raise HTTPException(404, f"no message of '/{name.lstrip('/')}' before t = {view.time:.3f} s")
        return message

    @app.websocket("/topics/{name:path}/stream")
    async def stream(websocket: WebSocket, name: str, rate: float = Query(10.0, gt=0.0, le=1000.0)) -> None:
        topic = "/" + name.lstrip("/")
        if topic not in playback.topics:
            await websocket.close(code=1008, reason=f"topic '{topic}' was not recorded")
            return
        await websocket.accept()
        last = None
        try:
            while True:
                message = playback.message_at(topic, view.time)
                if message is not None and message != last:
                    last = message
                    await websocket.send_json(message)
                await asyncio.sleep(1.0 / rate)
        except (WebSocketDisconnect, RuntimeError):
            return

    @app.get("/replay", summary="The playback: file, duration, time, playing, speed, 3D view")
    def state() -> dict:
        return {
            "file": str(playback.path),
            "duration": playback.duration,
            "time": view.time,
            "playing": view.playing,
            "speed": view.speed,
            "view": view.url,
        }

    return app
