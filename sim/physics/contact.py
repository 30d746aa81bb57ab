"""Spring contact model: a flat rectangular patch (robot plate or human palm) against a box face.

The patch is sampled as a grid of points (patch frame: x, y in the patch plane, +z = outward
normal, pointing into the box when touching). For each point i that lies inside the box:

    depth_i  = penetration below the box face it is pressed on (m)
    f_n,i    = max(0, k d_i + c d'_i)                    normal spring-damper (N), own depth
    z_i     += v_t,i dt                                  bristle = tangential slide of the patch
    |k_t z_i| > mu f_n,i  ->  z_i scaled to |k_t z_i| = mu f_n,i   (the bristle slips)
    f_t,i    = k_t z_i + c_t v_t,i (stick) , |f_t,i| <= mu f_n,i

(an elastoplastic, stick-slip bristle friction: a squeezed box sticks without creeping and
slides once the cone is left). k, c, k_t, c_t are the patch totals divided by the number of
points. Sums give the force, the moment, and the centre of pressure; a tilted patch presses
harder at one edge and so yields a moment and a shifted centre of pressure.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numba import njit

from sim.spatial import norm3


@dataclass(frozen=True)
class PatchGeometry:
    """Rectangle of width x height (m) sampled as nx x ny points at cell centres."""

    width: float
    height: float
    nx: int = 6
    ny: int = 6

    def points(self) -> np.ndarray:
        """(N, 3) sample points in the patch frame (z = 0)."""
        xs = (np.arange(self.nx) + 0.5) / self.nx * self.width - self.width / 2
        ys = (np.arange(self.ny) + 0.5) / self.ny * self.height - self.height / 2
        gx, gy = np.meshgrid(xs, ys, indexing="ij")
        return np.column_stack((gx.ravel(), gy.ravel(), np.zeros(gx.size)))

    @property
    def mean_radius(self) -> float:
        """Mean distance of the sample points to the centre (m)."""
        return float(np.mean(np.linalg.norm(self.points()[:, :2], axis=1)))


@dataclass(frozen=True)
class ContactParams:
    """Material of one contact; stiffness and damping are totals for the whole patch."""

    normal_stiffness: float = 2.0e4  # N/m (rubber pad on cardboard: 0.5 mm at 10 N)
    normal_damping: float = 150.0  # N s/m
    tangential_stiffness: float = 1.0e4  # N/m (bristles)
    tangential_damping: float = 80.0  # N s/m
    mu: float = 0.6  # Coulomb friction coefficient


@dataclass
class ContactResult:
    """What one patch does to the box at this instant (world frame)."""

    force_box: np.ndarray  # force on the box (N)
    torque_box: np.ndarray  # moment on the box about its centre (Nm)
    moment_patch: np.ndarray  # moment on the box about the patch centre (Nm)
    normal_force: float  # sum of the point normal forces (N)
    tangential_force: np.ndarray  # tangential part of force_box (N)
    normal_world: np.ndarray  # the pressed face's inward normal = patch push direction
    centre_of_pressure: np.ndarray  # (x, y) in the patch frame (m); (0, 0) when not touching
    points_in_contact: int
    points_slipping: int

    @property
    def friction_ratio(self) -> float:
        """|f_t| / f_n (compare with mu); 0 without contact."""
        if self.normal_force <= 1e-9:
            return 0.0
        return norm3(self.tangential_force) / self.normal_force


@dataclass
class BoxPose:
    """The box's state as the contact needs it (world frame)."""

    position: np.ndarray  # centre (m)
    rotation: np.ndarray  # box -> world
    velocity: np.ndarray  # of the centre (m/s)
    angular_velocity: np.ndarray  # rad/s
    half_size: np.ndarray  # half extents along the box axes (m)


@dataclass
class PatchContact:
    """One patch with its bristle state."""

    geometry: PatchGeometry
    params: ContactParams
    points_patch: np.ndarray = field(init=False)
    bristles: np.ndarray = field(init=False)  # (N, 3) world, m

    def __post_init__(self) -> None:
        self.points_patch = self.geometry.points()
        self.bristles = np.zeros_like(self.points_patch)
        self._set_point_constants()

    def _set_point_constants(self) -> None:
        n = len(self.points_patch)
        p = self.params
        self._k, self._c = p.normal_stiffness / n, p.normal_damping / n
        self._kt, self._ct = p.tangential_stiffness / n, p.tangential_damping / n
        self.constants = np.array([self._k, self._c, self._kt, self._ct, p.mu])  # what patch_step reads

    def set_params(self, params: ContactParams) -> None:
        self.params = params
        self._set_point_constants()

    def reset(self) -> None:
        self.bristles[:] = 0.0

    def step(
        self,
        rotation_patch_to_world: np.ndarray,
        position_patch: np.ndarray,
        velocity_patch: np.ndarray,
        angular_velocity_patch: np.ndarray,
        box: BoxPose,
        dt: float,
    ) -> ContactResult:
        """Contact forces for one time step dt (s); advances the bristles."""
        out = np.empty(20)
        return result_of(
            self.step_into(
                rotation_patch_to_world, position_patch, velocity_patch, angular_velocity_patch, box, dt, out
            )
        )

    def step_into(
        self,
        rotation_patch_to_world,
        position_patch,
        velocity_patch,
        angular_velocity_patch,
        box: BoxPose,
        dt: float,
        out: np.ndarray,
    ) -> np.ndarray:
        """`step` into the array `out` (_patch_kernel's layout)."""
        _patch_kernel(
            self.points_patch,
            rotation_patch_to_world,
            position_patch,
            velocity_patch,
            angular_velocity_patch,
            box.position,
            box.rotation,
            box.velocity,
            box.angular_velocity,
            box.half_size,
            self.bristles,
            self._k,
            self._c,
            self._kt,
            self._ct,
            self.params.mu,
            dt,
            out,
        )
        return out


# where _patch_kernel writes each figure in its `out` array (ContactResult's fields; world frame)
FORCE_BOX, TORQUE_BOX, MOMENT_PATCH = slice(0, 3), slice(3, 6), slice(6, 9)
NORMAL_FORCE, TANGENTIAL_FORCE, CENTRE_OF_PRESSURE = 9, slice(10, 13), slice(13, 15)
POINTS_IN_CONTACT, POINTS_SLIPPING, NORMAL_WORLD = 15, 16, slice(17, 20)


def result_of(out: np.ndarray) -> ContactResult:
    """The ContactResult of a kernel's `out` array (its own copies of the numbers)."""
    out = out.copy()
    return ContactResult(
        force_box=out[FORCE_BOX],
        torque_box=out[TORQUE_BOX],
        moment_patch=out[MOMENT_PATCH],
        normal_force=float(out[NORMAL_FORCE]),
        tangential_force=out[TANGENTIAL_FORCE],
        normal_world=out[NORMAL_WORLD],
        centre_of_pressure=out[CENTRE_OF_PRESSURE],
        points_in_contact=int(out[POINTS_IN_CONTACT]),
        points_slipping=int(out[POINTS_SLIPPING]),
    )


@njit(cache=True)
def patch_step(points, bristles, constants, rot_p, pos_p, vel_p, omg_p, pos_b, rot_b, vel_b, omg_b, half, dt, out):
    """_patch_kernel with the patch's constants array (PatchContact.constants: k, c, k_t, c_t, mu)."""
    _patch_kernel(
        points,
        rot_p,
        pos_p,
        vel_p,
        omg_p,
        pos_b,
        rot_b,
        vel_b,
        omg_b,
        half,
        bristles,
        constants[0],
        constants[1],
        constants[2],
        constants[3],
        constants[4],
        dt,
        out,
    )


@njit(cache=True)
def _patch_kernel(
    pts, rot_p, pos_p, vel_p, omg_p, pos_b, rot_b, vel_b, omg_b, half, bristles, k, c, kt, ct, mu, dt, out
):
    """The per-point loop of the module docstring (numba: ~1 us instead of ~100 us of numpy calls).

    out = [force(3), torque about box centre(3), moment about patch centre(3), f_n, f_t(3),
           cop(2), points in contact, points slipping, inward normal(3)], all world frame."""
    out[:] = 0.0
    # The pressed face is the one whose outward normal opposes the patch normal (patch z).
    axis = 0
    best = -1.0
    comp = 0.0
    for a in range(3):
        na = rot_b[0, a] * rot_p[0, 2] + rot_b[1, a] * rot_p[1, 2] + rot_b[2, a] * rot_p[2, 2]
        if abs(na) > best:
            best, axis, comp = abs(na), a, na
    side = -1.0 if comp > 0.0 else 1.0  # outward face normal = side * box axis
    n0, n1, n2 = -side * rot_b[0, axis], -side * rot_b[1, axis], -side * rot_b[2, axis]
    o1, o2 = (axis + 1) % 3, (axis + 2) % 3
    fx = fy = fz = tx = ty = tz = fn_sum = cop_x = cop_y = 0.0
    n_in = n_slip = 0
    for i in range(pts.shape[0]):
        # point and lever arms (world)
        ax = rot_p[0, 0] * pts[i, 0] + rot_p[0, 1] * pts[i, 1] + rot_p[0, 2] * pts[i, 2]
        ay = rot_p[1, 0] * pts[i, 0] + rot_p[1, 1] * pts[i, 1] + rot_p[1, 2] * pts[i, 2]
        az = rot_p[2, 0] * pts[i, 0] + rot_p[2, 1] * pts[i, 1] + rot_p[2, 2] * pts[i, 2]
        bx, by, bz = pos_p[0] + ax - pos_b[0], pos_p[1] + ay - pos_b[1], pos_p[2] + az - pos_b[2]
        l_axis = rot_b[0, axis] * bx + rot_b[1, axis] * by + rot_b[2, axis] * bz
        l_o1 = rot_b[0, o1] * bx + rot_b[1, o1] * by + rot_b[2, o1] * bz
        l_o2 = rot_b[0, o2] * bx + rot_b[1, o2] * by + rot_b[2, o2] * bz
        depth = half[axis] - side * l_axis
        if not (0.0 < depth < half[axis] and abs(l_o1) <= half[o1] and abs(l_o2) <= half[o2]):
            bristles[i, 0] = bristles[i, 1] = bristles[i, 2] = 0.0
            continue
        # relative velocity of the patch point w.r.t. the box point
        vx = vel_p[0] + omg_p[1] * az - omg_p[2] * ay - (vel_b[0] + omg_b[1] * bz - omg_b[2] * by)
        vy = vel_p[1] + omg_p[2] * ax - omg_p[0] * az - (vel_b[1] + omg_b[2] * bx - omg_b[0] * bz)
        vz = vel_p[2] + omg_p[0] * ay - omg_p[1] * ax - (vel_b[2] + omg_b[0] * by - omg_b[1] * bx)
        vn = vx * n0 + vy * n1 + vz * n2  # depth rate
        # normal spring-damper, pushing only: f_n = max(0, k d + c d')
        fn = max(k * depth + c * vn, 0.0)
        # bristle: z += v_t dt, kept in the tangent plane
        vtx, vty, vtz = vx - vn * n0, vy - vn * n1, vz - vn * n2
        zx, zy, zz = bristles[i, 0] + vtx * dt, bristles[i, 1] + vty * dt, bristles[i, 2] + vtz * dt
        zn = zx * n0 + zy * n1 + zz * n2
        zx, zy, zz = zx - zn * n0, zy - zn * n1, zz - zn * n2
        cap = mu * fn
        znorm = (zx * zx + zy * zy + zz * zz) ** 0.5
        slip = kt * znorm > cap
        if slip:  # the bristle slips: |k_t z| = mu f_n
            s = cap / (kt * znorm)
            zx, zy, zz = zx * s, zy * s, zz * s
            n_slip += 1
        bristles[i, 0], bristles[i, 1], bristles[i, 2] = zx, zy, zz
        dmp = 0.0 if slip else ct
        gx, gy, gz = kt * zx + dmp * vtx, kt * zy + dmp * vty, kt * zz + dmp * vtz
        gnorm = (gx * gx + gy * gy + gz * gz) ** 0.5
        if gnorm > cap:  # |f_t| <= mu f_n
            s = cap / gnorm
            gx, gy, gz = gx * s, gy * s, gz * s
        px, py, pz = gx + fn * n0, gy + fn * n1, gz + fn * n2  # force on the box
        fx += px
        fy += py
        fz += pz
        tx += by * pz - bz * py
        ty += bz * px - bx * pz
        tz += bx * py - by * px
        fn_sum += fn
        cop_x += fn * pts[i, 0]
        cop_y += fn * pts[i, 1]
        n_in += 1
    # moment about the patch centre: tau_box - (p_patch - c_box) x f
    rx, ry, rz = pos_p[0] - pos_b[0], pos_p[1] - pos_b[1], pos_p[2] - pos_b[2]
    out[0], out[1], out[2] = fx, fy, fz
    out[3], out[4], out[5] = tx, ty, tz
    out[6] = tx - (ry * fz - rz * fy)
    out[7] = ty - (rz * fx - rx * fz)
    out[8] = tz - (rx * fy - ry * fx)
    out[9] = fn_sum
    fdotn = fx * n0 + fy * n1 + fz * n2
    out[10], out[11], out[12] = fx - fdotn * n0, fy - fdotn * n1, fz - fdotn * n2
    if fn_sum > 1e-12:
        out[13], out[14] = cop_x / fn_sum, cop_y / fn_sum
    out[15], out[16] = n_in, n_slip
    out[17], out[18], out[19] = n0, n1, n2
