"""The camera: the rendered image (sim/camera_render.py, OpenGL) and the lab's projection
(sim/camera.py, /get_target_position) agree: the box's blob, found as the handout finds it (an HSV
threshold, the largest contour's bounding rectangle), is centred within 5 px of the projection at
several poses, the robot's and the palm's colours do not pass the threshold, CameraInfo is the
model's K, and the camera process renders only while somebody wants images.

This pytest process never makes an OpenGL context itself: Mesa's llvmpipe keeps threads that a
fork does not copy, so a camera process forked after it (a lab run in-process by a later test
file) would wait forever for its first image. The renderer under test runs in a forked child
(`Rendering`), and the camera process's test comes last in the file: it fails should an earlier
test have made a context here."""

import dataclasses
import math
import multiprocessing
import time
from multiprocessing.connection import Connection

import cv2
import numpy as np
import pytest

from sim import camera
from sim.camera_render import CameraRenderer, SceneSizes, clip_from_optical
from sim.messages import camera_info_at, image
from sim.world import World, WorldConfig

from app.runtime.camera_process import CameraProcess
from app.runtime.shared_frame import SharedFrame
from tests.waiting import wait_for

TOLERANCE_PX = 5


def sizes_of(config: WorldConfig) -> SceneSizes:
    return SceneSizes((config.plate.width, config.plate.height, config.plate.offset), config.box.size, config.palm_size)


@pytest.fixture(scope="module")
def world():
    return World(WorldConfig())


class Rendering:
    """A CameraRenderer in a forked child (see the module's docstring): render(s) is its image of s."""

    def __init__(self, sizes: SceneSizes) -> None:
        fork = multiprocessing.get_context("fork")
        self._conn, child = fork.Pipe()
        self._process = fork.Process(target=_render_each, args=(sizes, child), daemon=True)
        self._process.start()
        child.close()

    def render(self, s) -> np.ndarray:
        self._conn.send(s)
        assert self._conn.poll(120), "the renderer did not answer within 120 s"
        return self._conn.recv()

    def release(self) -> None:
        self._conn.send(None)
        self._process.join(30)
        self._conn.close()


def _render_each(sizes: SceneSizes, conn: Connection) -> None:
    renderer = CameraRenderer(sizes)
    while (s := conn.recv()) is not None:
        conn.send(renderer.render(s))
    renderer.release()


@pytest.fixture(scope="module")
def renderer(world):
    r = Rendering(sizes_of(world.config))
    yield r
    r.release()


def blob_centre(bgr: np.ndarray) -> tuple[int, int] | None:
    """The handout's detection: saturated, bright pixels, the largest contour's bounding rectangle."""
    mask = cv2.inRange(cv2.cvtColor(bgr, cv2.COLOR_BGR2HSV), np.array([0, 120, 80]), np.array([180, 255, 255]))
    contours, _ = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
    if not contours:
        return None
    x, y, w, h = cv2.boundingRect(max(contours, key=cv2.contourArea))
    return x + w // 2, y + h // 2


def rotation_z(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def wake_ups(pid: int) -> int:
    """The times the process's main thread went to sleep and was woken (voluntary context switches)."""
    with open(f"/proc/{pid}/status") as status:
        return next(int(line.split()[1]) for line in status if line.startswith("voluntary_ctxt_switches"))


def test_the_projection_of_a_point_is_k_times_the_optical_frames_coordinates():
    """By hand: the optical axis lands on the principal point; 0.1 m to the camera's right at
    depth d lands f * 0.1 / d px right of it."""
    k = camera.intrinsics()
    assert camera.project(camera.CAMERA_TARGET) == (320, 240)
    rotation = camera.rotation_optical_to_base()
    depth = np.linalg.norm(camera.CAMERA_TARGET - camera.CAMERA_POSITION)
    u, v = camera.project_exact(camera.CAMERA_TARGET + 0.1 * rotation[:, 0])
    assert u == pytest.approx(320 + 500 * 0.1 / depth)
    assert v == pytest.approx(240)
    info = camera_info_at(1.5)
    assert info["k"] == k.flatten().tolist()
    assert info["header"]["frame_id"] == "camera_optical"
    with pytest.raises(ValueError, match="behind"):
        camera.project(camera.CAMERA_POSITION - rotation[:, 2])


def test_opengls_projection_puts_a_point_on_the_pixel_k_gives():
    """clip_from_optical is K: a point's normalised device coordinates map to K's pixel (+0.5:
    OpenGL's pixel centres)."""
    k = camera.intrinsics()
    point = np.array([0.13, -0.07, 1.3, 1.0])  # optical frame, m
    clip = clip_from_optical(640, 480, k) @ point
    ndc = clip[:3] / clip[3]
    column = (ndc[0] + 1) / 2 * 640 - 0.5
    row = (1 - ndc[1]) / 2 * 480 - 0.5
    assert column == pytest.approx(320 + 500 * 0.13 / 1.3)
    assert row == pytest.approx(240 + 500 * -0.07 / 1.3)


def poses(world):
    """The start pose; the box moved, turned and raised; the robot at another q; a carried box
    (the scripted person's carry, stepped)."""
    s = world.snapshot()
    yield "start", s
    yield "moved", dataclasses.replace(s, box_position=s.box_position + [-0.15, 0.05, 0.10])
    yield "turned", dataclasses.replace(s, box_rotation=rotation_z(0.4) @ s.box_rotation)
    yield "robot elsewhere", dataclasses.replace(s, q=s.q + np.array([0.3, -0.2, 0.0, 0.2, 0.0, 0.1, 0.0]))
    carried = World(WorldConfig())
    carried.start_lifting(10.0)
    while np.linalg.norm(carried.box.position - s.box_position) < 0.1 and carried.time < 30.0:
        carried.step()
    assert carried.human.phase == "carrying"
    yield "carried", carried.snapshot()


def test_the_rendered_box_is_where_the_projection_says_at_several_poses(world, renderer):
    start = world.snapshot().box_position
    for name, s in poses(world):
        if name == "carried":
            assert np.linalg.norm(s.box_position - start) > 0.05  # the box did move
            assert s.plate.normal_force > 0
            assert s.palm.normal_force > 0
        bgr = renderer.render(s)
        assert bgr.shape == (480, 640, 3)
        assert bgr.dtype == np.uint8
        found = blob_centre(bgr)
        expected = camera.box_in_image(s.box_position, s.box_rotation, world.config.box.size)
        assert found is not None, name
        assert max(abs(found[0] - expected[0]), abs(found[1] - expected[1])) <= TOLERANCE_PX, (name, found, expected)


def test_only_the_box_passes_the_threshold(world, renderer):
    """Without the box (moved far behind the camera's view) nothing in the image is saturated: the
    robot is drawn in greys, the palm in an unsaturated skin tone."""
    s = world.snapshot()
    gone = dataclasses.replace(s, box_position=np.array([0.0, 0.0, -5.0]))
    assert blob_centre(renderer.render(gone)) is None
    message = image(0.25, renderer.render(s))
    assert message["encoding"] == "bgr8"
    assert message["step"] == 1920
    assert message["header"]["stamp"]["nanosec"] == 25e7


def test_a_shared_frame_is_read_whole_with_its_stamp():
    frames = SharedFrame(4, 2)
    assert frames.read() is None
    picture = np.arange(24, dtype=np.uint8).reshape(2, 4, 3)
    frames.write(picture, 1.25, 100.0, 0.01)
    frame = frames.read()
    assert frame is not None
    assert frame.number == 1
    assert frame.time == 1.25
    assert np.array_equal(frame.image, picture)


def test_the_camera_process_renders_only_while_wanted(world):
    """Idle, it sleeps until a demand wakes it (it looked at the demand every 20 ms before: ~50
    wake-ups a second in every idle lab; a busy machine wakes it less often, never more); wanted,
    it renders. (Last in the file: forked after the renderer's tests, it renders only if they left
    no OpenGL context in this process.)"""
    process = CameraProcess(world.snapshot, lambda: sizes_of(world.config))
    process.start()
    try:
        assert process.number == 0
        assert not process.wanted
        time.sleep(0.3)  # its start done
        before = wake_ups(process.pid)
        time.sleep(1.0)  # a window to count its wake-ups in
        assert wake_ups(process.pid) - before <= 5
        with process.wants(0.05):
            assert process.wanted
            wait_for(lambda: process.number >= 2 or process.error, timeout=120)
            assert not process.error
        frame = process.latest()
        assert frame is not None
        assert frame.image.shape == (480, 640, 3)
        assert frame.time == world.snapshot().time
        assert blob_centre(frame.image) is not None
        assert not process.wanted  # released: at most the frame being rendered then still comes
        released = process.number
        time.sleep(0.5)  # a window to see none come (a slow machine renders fewer, never more)
        assert process.number <= released + 1
    finally:
        process.stop()
    assert not process.running
