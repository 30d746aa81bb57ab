"""The patch controller: the paper's point made into a controller (Marullo et al., IEEE RA-L 2020,
"extended contact patches"). A flat plate pressed on a box is not a single point: it holds a
moment about its normal (torsional friction) and tipping moments as long as the centre of
pressure stays inside the plate. This reconstruction (ours; each step's source below):

1. Wrench at the plate (as SP): f_n = f_z, f_t = (f_x, f_y), m_c = m - p_c x f.
2. Centre of pressure on the plate (moment balance of a pressure distribution on the plane of
   the plate, offset d along the EE z axis):  p_x = (d f_x - m_y) / f_z,  p_y = (d f_y + m_x) / f_z,
   and the torsion about the normal at the centre of pressure:  m_n = m_z - (p_x f_y - p_y f_x).
3. Limit surface (Howe & Cutkosky 1996, elliptic approximation): the grip holds while
      s = (|f_t| / (mu f_n))^2 + (m_n / (mu f_n r_eq))^2 <= 1,
   r_eq = mean distance of the patch's points to its centre; we keep s <= alpha^2 (margin).
   Tipping (Caron et al., ICRA 2015, contact wrench cone): the centre of pressure must stay inside
   the plate; we keep it inside the plate shrunk by the edge margin beta.
4. Normal: the band of SP; while s > alpha^2 the grip is raised toward f_n_max (s shrinks as f_n grows).
5. Tangential: the friction force the patch still holds given the torsion,
      f_t,max = alpha mu f_n sqrt(1 - (m_n / (alpha mu f_n r_eq))^2),
   beyond it v_t = -k_t (|f_t| - f_t,max) f_t/|f_t| (against f_t, with the person, as in SP).
6. Rotation: resist what the patch can hold, comply only with the excess:
      tipping: m_xy,max = (1 - beta) (h/2, w/2) f_n; w_xy = -k_w (m_c,xy - clip(m_c,xy, +-m_xy,max))
      torsion: m_n,max = alpha mu f_n r_eq sqrt(1 - (|f_t|/(alpha mu f_n))^2); w_z = -k_w (excess of m_n)
7. Saturation, base frame and rate limit exactly as SP (steps 5-6 there).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .controller import LiftingParams
from .robot import Plate
from .sp_controller import SPController, _saturate


@dataclass(frozen=True)
class PatchGrip:
    """What the measured wrench says about the patch contact (EE frame, SI units)."""

    f_n: float
    f_t: np.ndarray  # (2,)
    cop: np.ndarray  # (2,) centre of pressure on the plate (m)
    m_c: np.ndarray  # (3,) moment about the plate centre (Nm)
    m_n: float  # torsion about the normal at the centre of pressure (Nm)
    limit_surface: float  # s; the grip holds while s <= 1


def patch_grip(wrench_ee: np.ndarray, plate_offset: float, mu: float, r_eq: float) -> PatchGrip:
    """Steps 1-3: centre of pressure, torsion and limit-surface value from F_ext."""
    fx, fy, fz, mx, my, mz = (float(x) for x in wrench_ee)
    d = plate_offset
    m_c = np.array([mx + d * fy, my - d * fx, mz])
    if fz <= 1e-9:
        return PatchGrip(fz, np.array([fx, fy]), np.zeros(2), m_c, mz, math.inf)
    px, py = (d * fx - my) / fz, (d * fy + mx) / fz
    m_n = mz - (px * fy - py * fx)
    s = (math.hypot(fx, fy) / (mu * fz)) ** 2 + (m_n / (mu * fz * r_eq)) ** 2
    return PatchGrip(fz, np.array([fx, fy]), np.array([px, py]), m_c, m_n, s)


class PatchController(SPController):
    """Patch-aware lifting: the SP band, friction following with the limit surface, and moments held."""

    edge_margin = 0.3  # beta: keep the centre of pressure within 70 % of the half sizes

    def __init__(self, plate: Plate = Plate(), r_eq: float | None = None) -> None:
        from .contact import PatchGeometry

        self.plate = plate
        self.r_eq = r_eq if r_eq is not None else PatchGeometry(plate.width, plate.height).mean_radius
        super().__init__()

    def twist_ee(self, wrench_ee: np.ndarray, params: LiftingParams) -> np.ndarray:
        grip = patch_grip(wrench_ee, params.plate_offset, params.mu, self.r_eq)
        f_n = grip.f_n
        in_contact = f_n >= params.f_contact
        # step 4: the band; raise the grip while the limit-surface margin is exceeded
        if f_n < params.f_n_min:
            v_n = params.k_n * (params.f_n_min - f_n)
        elif f_n > params.f_n_max:
            v_n = -params.k_n * (f_n - params.f_n_max)
        else:
            v_n = 0.0
        beyond = in_contact and grip.limit_surface > params.alpha**2
        if beyond and f_n < params.f_n_max:
            v_n = max(v_n, params.k_n * (params.f_n_max - f_n))
        v_t = np.zeros(2)
        w = np.zeros(3)
        self.slipping = beyond
        if in_contact:
            friction = params.alpha * params.mu * f_n
            # step 5: tangential following against the excess over what the patch holds
            torsion_share = min(1.0, (grip.m_n / (friction * self.r_eq)) ** 2)
            ft_max = friction * math.sqrt(1.0 - torsion_share)
            ft_norm = float(np.linalg.norm(grip.f_t))
            if ft_norm > ft_max:
                v_t = -params.k_t * (ft_norm - ft_max) * grip.f_t / ft_norm
            # step 6: hold moments the patch can hold, comply with the excess
            half = np.array([self.plate.height / 2, self.plate.width / 2])  # m_x <-> p_y, m_y <-> p_x
            hold_xy = (1.0 - self.edge_margin) * half * f_n
            excess_xy = grip.m_c[:2] - np.clip(grip.m_c[:2], -hold_xy, hold_xy)
            tangential_share = min(1.0, (ft_norm / friction) ** 2)
            hold_n = friction * self.r_eq * math.sqrt(1.0 - tangential_share)
            excess_n = grip.m_n - max(-hold_n, min(hold_n, grip.m_n))
            w = -params.k_w * np.array([excess_xy[0], excess_xy[1], excess_n])
        v = np.array([v_t[0], v_t[1], v_n])
        return np.concatenate((_saturate(v, params.v_max), _saturate(w, params.w_max)))
