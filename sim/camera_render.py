"""The image the lab's camera (sim/camera.py) sees, rendered with OpenGL (moderngl, an offscreen EGL
context: Mesa's llvmpipe on a machine without a GPU): the Panda with its visual meshes, the plate,
the box, the person's palm and the floor, lit by one directional light.

Colours, chosen for the handouts' detection exercise (an HSV threshold for saturated, bright
colours): the box is the only saturated thing in view (BOX_BGR); the robot is drawn in the greys of
its materials (its small coloured marks too), the palm in an unsaturated skin tone, the floor and
the background grey.

The Panda's meshes are read once with trimesh (seconds for the .dae files) and kept as arrays in
the mesh cache (sim/robot/assets.py, `mesh_cache`), keyed by file and trimesh version.
"""

from __future__ import annotations

import hashlib
import os
from dataclasses import dataclass
from importlib.metadata import version
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin

from sim import camera
from sim.robot.assets import mesh_cache, panda_urdf, robot_data_share
from sim.robot.panda import PandaModel
from sim.world import Snapshot

BOX_BGR = (30, 200, 30)  # a saturated green (HSV about 60, 217, 200 in OpenCV's 0-180 hue)
PALM_BGR = (160, 190, 230)  # skin, saturation about 30 %
PLATE_BGR = (60, 60, 60)
FLOOR_BGR = (150, 150, 150)
BACKGROUND_BGR = (215, 210, 205)
NOT_SHOWN = ("panda_hand", "panda_leftfinger", "panda_rightfinger")  # the lab's EE is the plate, no gripper
NEAR_M, FAR_M = 0.05, 10.0  # clipping planes
LIGHT_DIRECTION = np.array([0.3, 0.6, 1.0])  # towards the light, base frame
KEEP_FACES = 0.1  # share of a Panda mesh's triangles kept (fast-simplification's quadric decimation)
MIN_FACES = 200  # a part with fewer is kept whole
CACHE_FORMAT = (1, KEEP_FACES, MIN_FACES)  # a change of how link_arrays converts makes a new cache entry
AMBIENT = 0.5  # share of a colour lit whatever the face's direction (a side face stays bright)


@dataclass(frozen=True)
class SceneSizes:
    """What the camera draws that does not move (m): plate (width, height, offset along the flange
    z), box (x, y, z), palm (x, y)."""

    plate: tuple[float, float, float]
    box: tuple[float, float, float]
    palm: tuple[float, float]


_VERTEX = """
#version 330
uniform mat4 clip_from_base;
uniform mat4 base_from_object;
in vec3 position;
in vec3 normal;
in vec3 colour;
out vec3 v_normal;
out vec3 v_colour;
void main() {
    gl_Position = clip_from_base * base_from_object * vec4(position, 1.0);
    v_normal = mat3(base_from_object) * normal;
    v_colour = colour;
}
"""
_FRAGMENT = """
#version 330
uniform vec3 light;
uniform float ambient;
in vec3 v_normal;
in vec3 v_colour;
out vec4 colour;
void main() {
    float lit = ambient + (1.0 - ambient) * abs(dot(normalize(v_normal), light));
    colour = vec4(v_colour * lit, 1.0);
}
"""


def clip_from_optical(width: int, height: int, k: np.ndarray) -> np.ndarray:
    """OpenGL's projection (4x4) of the pinhole K: optical frame (x right, y down, z forward) to clip
    space, so a point lands on the pixel K gives (OpenCV's pixel centres: pixel i spans i-0.5..i+0.5)."""
    fx, fy, cx, cy = k[0, 0], k[1, 1], k[0, 2] + 0.5, k[1, 2] + 0.5
    n, f = NEAR_M, FAR_M
    # eye = (x, -y, -z) of the optical frame; then the usual frustum with its centre at (cx, cy)
    projection = np.array(
        [
            [2 * fx / width, 0.0, 1 - 2 * cx / width, 0.0],
            [0.0, 2 * fy / height, 2 * cy / height - 1, 0.0],
            [0.0, 0.0, -(f + n) / (f - n), -2 * f * n / (f - n)],
            [0.0, 0.0, -1.0, 0.0],
        ]
    )
    return projection @ np.diag([1.0, -1.0, -1.0, 1.0])


def box_arrays(size, bgr) -> np.ndarray:
    """A box centred on its origin (m) as rows of position, normal, colour (0-1, RGB): 36 vertices."""
    half = np.asarray(size, float) / 2
    rows = []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            normal = np.zeros(3)
            normal[axis] = sign
            u, v = np.eye(3)[(axis + 1) % 3], np.eye(3)[(axis + 2) % 3]
            corners = [(normal + a * u + b * v) * half for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
            for index in (0, 1, 2, 0, 2, 3):
                rows.append(np.concatenate((corners[index], normal, np.asarray(bgr[::-1]) / 255.0)))
    return np.array(rows, dtype="f4")


def grey(rgb: np.ndarray) -> np.ndarray:
    """A colour's luminance as a grey (0-1, Rec. 601 weights, OpenCV's)."""
    luminance = rgb @ np.array([0.299, 0.587, 0.114])
    return np.repeat(luminance[..., None], 3, axis=-1)


def link_arrays(mesh_path: Path, scale) -> np.ndarray:
    """One of the Panda's meshes as rows of position (m, the link's frame), normal, grey colour:
    read with trimesh once, then from the mesh cache."""
    stat = mesh_path.stat()
    key = hashlib.sha1(
        repr(
            (str(mesh_path.resolve()), stat.st_size, stat.st_mtime_ns, tuple(scale), version("trimesh"), CACHE_FORMAT)
        ).encode()
    ).hexdigest()
    cached = mesh_cache() / f"{mesh_path.stem}-camera-{key[:16]}.npy"
    try:
        return np.load(cached)
    except (OSError, ValueError):
        pass
    import trimesh

    scene: Any = trimesh.load(str(mesh_path), force="scene")
    parts = []
    for node in scene.graph.nodes_geometry:
        transform, name = scene.graph[node]
        mesh = scene.geometry[name].copy()
        mesh.apply_transform(transform)
        mesh.apply_scale(np.asarray(scale, float))
        mesh.merge_vertices()  # the .dae triangles share no vertices; decimation needs them joined
        if len(mesh.faces) > MIN_FACES:  # low-poly: the software renderer's time goes with the triangles
            mesh = mesh.simplify_quadric_decimation(face_count=max(MIN_FACES, int(len(mesh.faces) * KEEP_FACES)))
        material = getattr(mesh.visual, "material", None)
        rgb = np.asarray(getattr(material, "main_color", (200, 200, 200, 255))[:3], float) / 255.0
        triangles = mesh.vertices[mesh.faces].reshape(-1, 3)
        normals = np.repeat(mesh.face_normals, 3, axis=0)
        parts.append(np.column_stack((triangles, normals, np.tile(grey(rgb), (len(triangles), 1)))))
    arrays = np.concatenate(parts).astype("f4")
    try:  # best effort: a read-only home only costs the conversion next time
        cached.parent.mkdir(parents=True, exist_ok=True)
        partial = cached.with_name(f"{cached.stem}.{os.getpid()}.tmp.npy")
        np.save(partial, arrays)
        partial.replace(cached)
    except OSError:
        pass
    return arrays


class CameraRenderer:
    """Renders snapshots as the camera's BGR image (height x width x 3, uint8)."""

    def __init__(self, sizes: SceneSizes) -> None:
        import moderngl

        gl: Any = moderngl  # its stubs lag its API (backend=, uniforms by name)
        self.width, self.height = camera.CAMERA_SIZE
        self.context = gl.create_standalone_context(backend="egl")
        ctx = self.context
        self.program: Any = ctx.program(vertex_shader=_VERTEX, fragment_shader=_FRAGMENT)
        self.framebuffer = ctx.simple_framebuffer((self.width, self.height), components=4)
        light = LIGHT_DIRECTION / np.linalg.norm(LIGHT_DIRECTION)
        self.program["light"].value = tuple(light)
        self.program["ambient"].value = AMBIENT
        base_from_optical = camera.transform_optical_to_base()
        clip_from_base = clip_from_optical(self.width, self.height, camera.intrinsics()) @ np.linalg.inv(
            base_from_optical
        )
        self.program["clip_from_base"].write(clip_from_base.T.astype("f4").tobytes())  # column-major
        self.sizes = sizes
        self.model = PandaModel()
        self.geometry = pin.buildGeomFromUrdf(
            self.model.model, str(panda_urdf()), pin.GeometryType.VISUAL, package_dirs=[str(robot_data_share())]
        )
        self.geometry_data = pin.GeometryData(self.geometry)
        self.links: list[tuple[int, object]] = []  # (geometry index, vertex array)
        for index, obj in enumerate(self.geometry.geometryObjects):
            if obj.name.startswith(NOT_SHOWN) or not obj.meshPath.lower().endswith((".dae", ".stl", ".obj")):
                continue
            self.links.append((index, self._vertex_array(link_arrays(Path(obj.meshPath), obj.meshScale))))
        plate_width, plate_height, self.plate_offset = sizes.plate
        self.plate = self._vertex_array(box_arrays((plate_width, plate_height, 0.006), PLATE_BGR))
        self.box = self._vertex_array(box_arrays(sizes.box, BOX_BGR))
        self.palm = self._vertex_array(box_arrays((*sizes.palm, 0.015), PALM_BGR))
        self.floor = self._vertex_array(box_arrays((4.0, 4.0, 0.01), FLOOR_BGR))

    def _vertex_array(self, arrays: np.ndarray):
        buffer = self.context.buffer(np.ascontiguousarray(arrays, dtype="f4").tobytes())
        return self.context.vertex_array(self.program, [(buffer, "3f 3f 3f", "position", "normal", "colour")])

    def _draw(self, vertex_array, base_from_object: np.ndarray) -> None:
        self.program["base_from_object"].write(np.asarray(base_from_object, "f4").T.tobytes())
        vertex_array.render()

    def render(self, s: Snapshot) -> np.ndarray:
        """The image of the scene in snapshot s: BGR, uint8, (height, width, 3), row 0 at the top."""
        import moderngl

        fb = self.framebuffer
        fb.use()
        red, green, blue = (channel / 255.0 for channel in BACKGROUND_BGR[::-1])
        fb.clear(red=red, green=green, blue=blue, alpha=1.0, depth=1.0)
        self.context.enable(moderngl.DEPTH_TEST)
        pin.framesForwardKinematics(self.model.model, self.model.data, s.q)
        pin.updateGeometryPlacements(self.model.model, self.model.data, self.geometry, self.geometry_data)
        for index, vertex_array in self.links:
            self._draw(vertex_array, self.geometry_data.oMg[index].homogeneous)
        flange = s.transform_ee_to_base
        plate = flange.copy()
        plate[:3, 3] = flange[:3, 3] + flange[:3, 2] * (self.plate_offset - 0.003)
        self._draw(self.plate, plate)
        self._draw(self.box, _pose(s.box_position, s.box_rotation))
        self._draw(self.palm, _pose(s.palm_position, s.palm_rotation))
        self._draw(self.floor, _pose(np.array([0.0, 0.0, -0.005]), np.eye(3)))
        rgb = np.frombuffer(fb.read(components=3), np.uint8).reshape(self.height, self.width, 3)
        return np.ascontiguousarray(rgb[::-1, :, ::-1])  # OpenGL's rows are bottom-up; RGB -> BGR

    def release(self) -> None:
        self.context.release()


def _pose(position: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    transform = np.eye(4)
    transform[:3, :3] = rotation
    transform[:3, 3] = position
    return transform
