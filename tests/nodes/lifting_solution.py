"""The lifting node template filled in with the SP law (what a student hands in for Exercise 16)."""

import math

import numpy as np

from app.cli.templates import lab_defaults
from app.cli.templates import lifting_node as node

node.PARAMS.update(lab_defaults())  # what `hri-lab template node` writes into the file


def start(request, response):
    node.lifting.update(f_n_min=request["force"], running=True)
    response["message"] = (
        f"Cooperative Lifting started with f_n_min = {request['force']:g} N, f_n_max = {request['force'] + 5:g} N."
    )
    return True


def stop(request, response):
    node.lifting.update(f_n_min=0.0, running=False)
    response["message"] = "Cooperative Lifting was stopped! Force limit f_n_min reset to 0 N."
    return True


def saturate(x, limit):
    norm = np.linalg.norm(x)
    return x * (limit / norm) if norm > limit else x


def law(wrench_ee, f_n_min, p):
    fx, fy, fz, mx, my, mz = wrench_ee
    d, f_n, f_n_max = p["plate_offset"], fz, f_n_min + p["f_n_band"]
    mc = np.array([mx + d * fy, my - d * fx, mz])  # m_c = m - p_c x f
    contact = f_n >= p["f_contact"]
    v_n = p["k_n"] * (f_n_min - f_n) if f_n < f_n_min else (-p["k_n"] * (f_n - f_n_max) if f_n > f_n_max else 0.0)
    vx = vy = 0.0
    ft, limit = math.hypot(fx, fy), p["alpha"] * p["mu"] * max(f_n, 0.0)
    if contact and ft > limit:
        excess = 1.0 - limit / ft
        vx, vy = -p["k_t"] * excess * fx, -p["k_t"] * excess * fy
        if f_n < f_n_max:
            v_n = max(v_n, p["k_n"] * (f_n_max - f_n))
    w = np.zeros(3)
    norm = np.linalg.norm(mc)
    if contact and norm > p["moment_deadband"]:
        w = -p["k_w"] * (1.0 - p["moment_deadband"] / norm) * mc
    return np.concatenate((saturate(np.array([vx, vy, v_n]), p["v_max"]), saturate(w, p["w_max"])))


if __name__ == "__main__":
    node.main(law, start, stop)
