"""The patch controller: the paper's point made into a controller (Marullo et al., IEEE RA-L 2020,
"extended contact patches"). A flat plate pressed on a box is not a single point: it holds a
moment about its normal (torsional friction) and tipping moments as long as the centre of
pressure stays inside the plate. This reconstruction is ours; each step names its source. These are
"patch step N" elsewhere; a plain "step N" is SP's (docs/method.md).

1. Wrench at the plate (SP's step 1): f_n = f_z, f_t = (f_x, f_y), m_c = m - p_c x f, p_c = (0, 0, d).
   Tangential forces act in the plate plane, so they add nothing to m_c: m_c,xy = (p_y f_n, -p_x f_n).
2. Centre of pressure on the plate (moment balance of a pressure distribution on the plane of
   the plate, offset d along the EE z axis):  p_x = (d f_x - m_y) / f_z,  p_y = (d f_y + m_x) / f_z,
   and the torsion about the normal at the centre of pressure:  m_n = m_z - (p_x f_y - p_y f_x).
3. Limit surface (Howe & Cutkosky, "Practical force-motion models for sliding manipulation",
   IJRR 1996; elliptic approximation): the patch does not slide while
      s = (|f_t| / (mu f_n))^2 + (m_n / (mu f_n r_eq))^2 <= 1,
   r_eq = mean distance of the patch's points to its centre; we keep s <= alpha^2 (SP's margin).
   Torsion deadband: m_n is used as m_n' = sign(m_n) max(|m_n| - db_n, 0), db_n = 0.025 Nm, about 3
   std of the torsion noise after the sensor (0.05 Nm) and the controller's 10 Hz low-pass at 1 kHz
   (std x sqrt(a / (2 - a)), a = 0.059: 0.0087 Nm), so noise does not eat the tangential allowance.
4. Tipping (Caron, Pham, Nakamura, "Stability of surface contacts for humanoid robots: closed-form
   formulae of the contact wrench cone for rectangular support areas", ICRA 2015): the contact
   does not tip while the centre of pressure is inside the plate, |p_x| <= W/2, |p_y| <= H/2. That is the limit, not the working region: with a compliant pad a moment
   is held only through a relative tilt of the plate on the box face, and once part of the plate
   lifts off, the contact becomes an edge contact whose normal is the box face's, not the plate's,
   so patch steps 3, 5 (measured in the plate frame) no longer describe it. The whole plate stays
   pressed while the centre of pressure is inside the kern (core) of the rectangle, the
   "middle-third" rule of a linear pressure distribution (e.g. Timoshenko & Gere, Mechanics of
   Materials, core of a section): p(x, y) = f_n/A (1 + 12 p_x x / W^2 + 12 p_y y / H^2) >= 0 at the
   corners  <=>  k = 6 |p_x| / W + 6 |p_y| / H <= 1  (W = plate width along EE x, H = height along y).
   So the patch holds tipping moments while k <= 1 and complies only beyond the kern.
5. Normal: SP's step 2 band; while s > alpha^2 the grip is raised toward f_n_max (s shrinks as f_n
   grows) - never above the band.
6. Tangential and torsional following, on the limit-surface margin: beyond the alpha-scaled limit
   surface, the excess is how far the wrench (f_t, m_n') is beyond its radial projection onto it,
      e = 1 - alpha / sqrt(s)   (the fraction of (f_t, m_n') outside the surface, 0 on it),
      v_t = -k_t e f_t          (against f_t, with the person, as in SP's step 3),
      w_n = -k_w e m_n'         (turn with the torsion the patch cannot hold).
   Without torsion this is exactly SP's law: e f_t = f_t - alpha mu f_n f_t/|f_t|.
7. Rotation about the plate axes: comply only with the part of m_c,xy beyond both the kern and the
   noise floor (SP's moment_deadband), along the same direction (radial projection, which brings
   the centre of pressure back to the kern's boundary):
      r = min(1, max(1 / k, db / |m_c,xy|)),   w_xy = -k_w (1 - r) m_c,xy.
8. Saturation, base frame and rate limit exactly as SP's steps 5a, 5b and 6.

Why the kern and not "inside the plate shrunk by a margin": holding the centre of pressure out to
70 % of the half size (an earlier version) let the box tilt about 6 deg on the plate during a lift;
the plate then touched the box along its upper edge, and the squeeze f_n along the tilted face
normal showed up in the plate frame as "less friction" (f_t,plate = f_t,face - f_n sin(tilt), about
1.5-2 N), so the robot followed the person later and the person's palm, already near its friction
cone, carried that extra drag and slipped (see tests/sim/controllers/test_tilt.py for the tilting case).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sim.controllers.interface import LiftingParams
from sim.controllers.lifting_law import PATCH, band_speed, grip_raise, saturate_twist
from sim.controllers.sp import SPController
from sim.physics.contact import PatchGeometry
from sim.robot.plate import Plate

# PatchController.constants(): what the compiled law reads besides the lifting parameters
R_EQ, PLATE_WIDTH, PLATE_HEIGHT, KERN_SCALE, TORSION_DEADBAND = range(5)


@dataclass(frozen=True)
class PatchGrip:
    """What the measured wrench says about the patch contact (EE frame, SI units)."""

    f_n: float
    f_t: np.ndarray  # (2,)
    cop: np.ndarray  # (2,) centre of pressure on the plate (m)
    m_c: np.ndarray  # (3,) moment about the plate centre (Nm)
    m_n: float  # torsion about the normal at the centre of pressure (Nm)
    limit_surface: float  # s; the patch does not slide while s <= 1


def patch_grip(wrench_ee: np.ndarray, plate_offset: float, mu: float, r_eq: float) -> PatchGrip:
    """Patch steps 1-3: centre of pressure, torsion and limit-surface value from F_ext (no deadband)."""
    fx, fy, fz, mx, my, mz = (float(x) for x in wrench_ee)
    d = plate_offset
    m_c = np.array([mx + d * fy, my - d * fx, mz])
    if fz <= 1e-9:
        return PatchGrip(fz, np.array([fx, fy]), np.zeros(2), m_c, mz, math.inf)
    px, py = (d * fx - my) / fz, (d * fy + mx) / fz
    m_n = mz - (px * fy - py * fx)
    s = (math.hypot(fx, fy) / (mu * fz)) ** 2 + (m_n / (mu * fz * r_eq)) ** 2
    return PatchGrip(fz, np.array([fx, fy]), np.array([px, py]), m_c, m_n, s)


def kern_ratio(cop: np.ndarray, plate: Plate) -> float:
    """Patch step 4: k = 6 |p_x| / W + 6 |p_y| / H; the whole plate stays pressed while k <= 1 (the
    kern), and the centre of pressure is inside the plate while max(2|p_x|/W, 2|p_y|/H) <= 1."""
    return 6.0 * abs(float(cop[0])) / plate.width + 6.0 * abs(float(cop[1])) / plate.height


class PatchController(SPController):
    """Patch-aware lifting: the SP band, following on the limit-surface margin, moments held in the kern
    (compiled too: sim/controllers/compiled_law.py, tested equal)."""

    compiled_law = PATCH
    torsion_deadband = 0.025  # Nm, db_n of patch step 3 (about 3 std of the filtered torsion noise)

    def __init__(self, plate: Plate | None = None, r_eq: float | None = None, kern_scale: float = 1.0) -> None:
        """kern_scale scales the region where tipping moments are held (1 = the kern, patch step 4;
        larger values hold the centre of pressure further out, with part of the plate lifted off)."""
        self.plate = plate if plate is not None else Plate()
        self.r_eq = r_eq if r_eq is not None else PatchGeometry(self.plate.width, self.plate.height).mean_radius
        self.kern_scale = kern_scale
        super().__init__()

    def constants(self) -> np.ndarray:
        """(r_eq, plate width, height, kern_scale, torsion deadband) as the compiled law reads them."""
        return np.array([self.r_eq, self.plate.width, self.plate.height, self.kern_scale, self.torsion_deadband])

    def twist_ee(self, wrench_ee: np.ndarray, params: LiftingParams) -> np.ndarray:
        grip = patch_grip(wrench_ee, params.plate_offset, params.mu, self.r_eq)
        f_n = grip.f_n
        in_contact = f_n >= params.f_contact
        v_n = band_speed(f_n, params)  # patch step 5: the normal band (SP's step 2)
        v_t = np.zeros(2)
        w = np.zeros(3)
        self.slipping = False
        if in_contact:
            # patch step 3: limit surface with the torsion deadband
            m_n = math.copysign(max(abs(grip.m_n) - self.torsion_deadband, 0.0), grip.m_n)
            friction = params.mu * f_n
            s = (float(np.linalg.norm(grip.f_t)) / friction) ** 2 + (m_n / (friction * self.r_eq)) ** 2
            if s > params.alpha**2:
                # patch step 6: follow with the excess beyond the alpha-scaled limit surface
                self.slipping = True
                excess = 1.0 - params.alpha / math.sqrt(s)
                v_t = -params.k_t * excess * grip.f_t
                w[2] = -params.k_w * excess * m_n
                v_n = grip_raise(v_n, f_n, params)  # patch step 5: toward f_n_max while beyond the margin
            # patch step 7: tipping moments held inside the kern (and the noise floor), excess complied with
            m_xy = grip.m_c[:2]
            m_norm = float(np.linalg.norm(m_xy))
            if m_norm > 0.0:
                k = kern_ratio(grip.cop, self.plate) / self.kern_scale
                held = min(1.0, max(1.0 / k if k > 0.0 else math.inf, params.moment_deadband / m_norm))
                w[:2] = -params.k_w * (1.0 - held) * m_xy
        return saturate_twist(np.array([v_t[0], v_t[1], v_n]), w, params)  # patch step 8 (SP's step 5a)
