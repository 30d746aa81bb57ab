"""The built-in lifting laws (SP and patch, steps 0-6) as compiled code: what the compiled world
step (sim/compiled_step.py) runs for a built-in controller, in one call with the rest of the step.

The laws of record are the Python classes a student reads and subclasses (sim/controllers/sp.py,
patch.py, lifting_law.py: a sandboxed plug-in imports them, and never numba). This module is the
same law written for numba, on the controller's state array (`LiftingLawController.state`) and the
parameter vector `lifting_vector(params)`; tests/sim/controllers/test_compiled_law.py runs both, step after step,
at many random wrenches, poses and parameters, and fails if they differ.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from sim.controllers.interface import (
    A_MAX,
    ALPHA,
    DW_MAX,
    F_CONTACT,
    F_N_BAND,
    F_N_MIN,
    FILTER_HZ,
    K_N,
    K_T,
    K_W,
    MOMENT_DEADBAND,
    MU,
    PLATE_OFFSET,
    RUNNING,
    V_MAX,
    W_MAX,
)
from sim.controllers.lifting_law import FILTERED, HAS_FILTERED, PATCH, SLIPPING, TWIST_BASE
from sim.controllers.patch import KERN_SCALE, PLATE_HEIGHT, PLATE_WIDTH, R_EQ, TORSION_DEADBAND
from sim.physics.sensor import low_pass_gain


@njit(cache=True)
def lifting_law_step(kind, state, p, constants, wrench_ee, rotation, dt, out):
    """Steps 0-6 of the built-in law `kind` (lifting_law.SP or PATCH) into `out` (twist_base):
    the controller's state, p = lifting_vector(params), constants = the controller's constants()."""
    filtered = low_pass(state, wrench_ee, p, dt)  # step 0
    if p[RUNNING] == 0.0:
        twist_ee = np.zeros(6)
    elif kind == PATCH:
        twist_ee = patch_twist_ee(filtered, p, constants, state)
    else:
        twist_ee = sp_twist_ee(filtered, p, state)
    to_base_rate_limited(state, p, twist_ee, rotation, dt, out)  # steps 5b, 6


@njit(cache=True)
def band_speed(f_n, p):
    """Step 2, the normal band [f_n_min, f_n_max] (p: lifting_vector):
    f_n < f_n_min -> +k_n (f_n_min - f_n) (press, along +n); f_n > f_n_max -> -k_n (f_n - f_n_max)
    (release, along -n); inside -> 0."""
    f_n_max = p[F_N_MIN] + p[F_N_BAND]
    if f_n < p[F_N_MIN]:
        return p[K_N] * (p[F_N_MIN] - f_n)
    if f_n > f_n_max:
        return -p[K_N] * (f_n - f_n_max)
    return 0.0


@njit(cache=True)
def grip_raise(v_n, f_n, p):
    """Step 3's grip raise while the friction is beyond its margin: v_n = max(v_n, k_n (f_n_max - f_n))
    below f_n_max (press toward the top of the band, never above it)."""
    f_n_max = p[F_N_MIN] + p[F_N_BAND]
    return max(v_n, p[K_N] * (f_n_max - f_n)) if f_n < f_n_max else v_n


@njit(cache=True)
def saturate_into(out, start, x, y, z, limit):
    """out[start:start+3] = (x, y, z) scaled down to length `limit` if longer (direction kept)."""
    norm = math.sqrt(x * x + y * y + z * z)
    scale = limit / norm if norm > limit else 1.0
    if norm > limit:
        out[start], out[start + 1], out[start + 2] = x * scale, y * scale, z * scale
    else:
        out[start], out[start + 1], out[start + 2] = x, y, z


@njit(cache=True)
def saturate_twist(vx, vy, vz, wx, wy, wz, p):
    """Step 5a: twist = [v, w] with |v| <= v_max and |w| <= w_max (directions kept)."""
    twist = np.empty(6)
    saturate_into(twist, 0, vx, vy, vz, p[V_MAX])
    saturate_into(twist, 3, wx, wy, wz, p[W_MAX])
    return twist


@njit(cache=True)
def rate_limit_into(previous, target, dv_max, dw_max, out):
    """Step 6: out = previous + (target - previous) with |dv| <= dv_max and |dw| <= dw_max."""
    delta = np.empty(6)
    saturate_into(delta, 0, target[0] - previous[0], target[1] - previous[1], target[2] - previous[2], dv_max)
    saturate_into(delta, 3, target[3] - previous[3], target[4] - previous[4], target[5] - previous[5], dw_max)
    for i in range(6):
        out[i] = previous[i] + delta[i]


@njit(cache=True)
def low_pass(state, wrench_ee, p, dt):
    """Step 0: the filtered F_ext, y <- y + a (x - y), a = dt / (tau + dt), tau = 1 / (2 pi filter_hz)
    (sim.signals.low_pass_gain; no filter for filter_hz <= 0 and at the first sample)."""
    filtered = state[FILTERED : FILTERED + 6]
    if p[FILTER_HZ] > 0.0 and state[HAS_FILTERED] != 0.0:
        a = low_pass_gain(dt, p[FILTER_HZ])
        for i in range(6):
            filtered[i] = filtered[i] + a * (wrench_ee[i] - filtered[i])
    else:
        filtered[:] = wrench_ee
    state[HAS_FILTERED] = 1.0
    return filtered.copy()


@njit(cache=True)
def to_base_rate_limited(state, p, twist_ee, rotation, dt, out):
    """Steps 5b and 6: twist_base = blockdiag(R, R) twist_ee, then rate limited from the last command."""
    target = np.empty(6)
    target[:3] = rotation @ twist_ee[:3]
    target[3:] = rotation @ twist_ee[3:]
    previous = state[TWIST_BASE : TWIST_BASE + 6]
    rate_limit_into(previous.copy(), target, p[A_MAX] * dt, p[DW_MAX] * dt, out)
    previous[:] = out


@njit(cache=True)
def sp_twist_ee(wrench_ee, p, state):
    """Steps 1-5a of the SP method (p = lifting_vector(params); the slipping flag into state)."""
    # Step 1: decompose. n = EE z (plate normal); f_n = n.f; f_t = f - f_n n;
    # m_c = m - p_c x f (moment about the plate centre p_c = [0, 0, d]; p_c x f = [-d fy, d fx, 0]).
    fx, fy, fz, mx, my, mz = wrench_ee[0], wrench_ee[1], wrench_ee[2], wrench_ee[3], wrench_ee[4], wrench_ee[5]
    d = p[PLATE_OFFSET]
    f_n = fz
    mcx, mcy, mcz = mx + d * fy, my - d * fx, mz
    in_contact = f_n >= p[F_CONTACT]

    # Step 2: normal band [f_n_min, f_n_max] (lifting_law.band_speed):
    #   f_n < f_n_min -> v_n = +k_n (f_n_min - f_n)   (press, along +n)
    #   f_n > f_n_max -> v_n = -k_n (f_n - f_n_max)   (release, along -n)
    #   otherwise     -> v_n = 0
    v_n = band_speed(f_n, p)

    # Step 3: tangential following, only while in contact (without contact there is no cone,
    # and sensor noise alone must not move the robot sideways).
    #   limit = alpha mu f_n; |f_t| <= limit -> the contact holds: v_t = 0
    #   beyond: e_t = f_t - limit f_t/|f_t|, v_t = -k_t e_t (move against f_t, with the person)
    #   and raise the grip toward f_n_max: v_n = max(v_n, k_n (f_n_max - f_n)).
    vx = vy = 0.0
    ft_norm = math.hypot(fx, fy)
    limit = p[ALPHA] * p[MU] * max(f_n, 0.0)
    slipping = in_contact and ft_norm > limit
    state[SLIPPING] = 1.0 if slipping else 0.0
    if slipping:
        excess = 1.0 - limit / ft_norm  # e_t = excess * f_t
        vx, vy = -p[K_T] * excess * fx, -p[K_T] * excess * fy
        v_n = grip_raise(v_n, f_n, p)

    # Step 4: rotation. A single point holds no moment: comply with it,
    #   w = -k_w (|m_c| - db)+ m_c/|m_c|   (deadband db against noise).
    wx = wy = wz = 0.0
    mc_norm = math.sqrt(mcx * mcx + mcy * mcy + mcz * mcz)
    if in_contact and mc_norm > p[MOMENT_DEADBAND]:
        gain = -p[K_W] * (1.0 - p[MOMENT_DEADBAND] / mc_norm)
        wx, wy, wz = gain * mcx, gain * mcy, gain * mcz

    # Step 5a: twist_ee = [v_t + v_n n, w], saturated at v_max, w_max (direction kept).
    return saturate_twist(vx, vy, v_n, wx, wy, wz, p)


@njit(cache=True)
def grip(fx, fy, fz, mx, my, mz, d, mu, r_eq):
    """Patch steps 1-3 (sim/controllers/patch.py) as numbers: (p_x, p_y, m_c,x, m_c,y, m_n, s); without
    pressure (f_z <= 0) the centre of pressure is (0, 0), m_n = m_z and s = inf."""
    mcx, mcy = mx + d * fy, my - d * fx
    if fz <= 1e-9:
        return 0.0, 0.0, mcx, mcy, mz, math.inf
    px, py = (d * fx - my) / fz, (d * fy + mx) / fz
    m_n = mz - (px * fy - py * fx)
    s = (math.hypot(fx, fy) / (mu * fz)) ** 2 + (m_n / (mu * fz * r_eq)) ** 2
    return px, py, mcx, mcy, m_n, s


@njit(cache=True)
def kern(px, py, width, height):
    """Patch step 4's k = 6 |p_x| / W + 6 |p_y| / H."""
    return 6.0 * abs(px) / width + 6.0 * abs(py) / height


@njit(cache=True)
def patch_twist_ee(wrench_ee, p, c, state):
    """Patch steps 1-7 (sim/controllers/patch.py) (p = lifting_vector(params), c = PatchController.constants();
    the slipping flag into state)."""
    fx, fy, fz, mx, my, mz = wrench_ee[0], wrench_ee[1], wrench_ee[2], wrench_ee[3], wrench_ee[4], wrench_ee[5]
    px, py, mcx, mcy, grip_m_n, _ = grip(fx, fy, fz, mx, my, mz, p[PLATE_OFFSET], p[MU], c[R_EQ])
    f_n = fz
    in_contact = f_n >= p[F_CONTACT]
    v_n = band_speed(f_n, p)  # patch step 5: the normal band (SP's step 2)
    vx = vy = 0.0
    wx = wy = wz = 0.0
    slipping = False
    if in_contact:
        # patch step 3: limit surface with the torsion deadband
        m_n = math.copysign(max(abs(grip_m_n) - c[TORSION_DEADBAND], 0.0), grip_m_n)
        friction = p[MU] * f_n
        s = (math.sqrt(fx * fx + fy * fy) / friction) ** 2 + (m_n / (friction * c[R_EQ])) ** 2
        if s > p[ALPHA] ** 2:
            # patch step 6: follow with the excess beyond the alpha-scaled limit surface
            slipping = True
            excess = 1.0 - p[ALPHA] / math.sqrt(s)
            vx, vy = -p[K_T] * excess * fx, -p[K_T] * excess * fy
            wz = -p[K_W] * excess * m_n
            v_n = grip_raise(v_n, f_n, p)  # patch step 5: toward f_n_max while beyond the margin
        # patch step 7: tipping moments held inside the kern (and the noise floor), excess complied with
        m_norm = math.sqrt(mcx * mcx + mcy * mcy)
        if m_norm > 0.0:
            k = kern(px, py, c[PLATE_WIDTH], c[PLATE_HEIGHT]) / c[KERN_SCALE]
            held = min(1.0, max(1.0 / k if k > 0.0 else math.inf, p[MOMENT_DEADBAND] / m_norm))
            wx, wy = -p[K_W] * (1.0 - held) * mcx, -p[K_W] * (1.0 - held) * mcy
    state[SLIPPING] = 1.0 if slipping else 0.0
    return saturate_twist(vx, vy, v_n, wx, wy, wz, p)  # patch step 8 (SP's step 5a)
