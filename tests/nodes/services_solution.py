"""The services template filled in (what a student hands in). Mistakes to grade, by flag:
`--wrong-torques`: compute_torques with F's force and moment swapped (tau = J^T [m, f]);
`--torques-as-force`: compute_torques answers tau = [F, 0] (no Jacobian at all)."""

import sys

import numpy as np

from app.cli.templates import services_node as node

MISTAKES = {flag for flag in ("--wrong-torques", "--torques-as-force") if flag in sys.argv}
for flag in MISTAKES:
    sys.argv.remove(flag)


def divide_ints(request, response):
    if request["b"] == 0:
        response["result"], response["message"] = 0.0, "Division by zero!"
    else:
        response["result"], response["message"] = request["a"] / request["b"], "Division ok."
    return True


def multiply_three(request, response):
    product = request["a"] * request["b"] * request["c"]
    if not node.INT64_MIN <= product <= node.INT64_MAX:
        response["error"] = f"a * b * c = {product} does not fit in int64"
        return False
    response["product"] = product
    return True


def echo(request, response):
    response["out"] = request["in"]
    return True


def login(request, response):
    name = request["username"]
    if not name.strip():
        response["success"], response["message"] = False, "Login failed: empty username."
    elif request["magic_number"] != 42:
        response["success"], response["message"] = False, f"Login failed: wrong magic number for {name}."
    else:
        response["success"], response["message"] = True, f"Welcome, {name}!"
    return True


def planar_torques(request, response):
    theta = np.cumsum(request["q"])
    force = np.append(request["force"], 0.0)[:3]
    sx = np.cumsum(np.sin(theta)[::-1])[::-1]
    cy = np.cumsum(np.cos(theta)[::-1])[::-1]
    response["torques"] = (np.vstack((-sx, cy, np.ones(3))).T @ force).tolist()
    return True


def jacobian():
    return np.array(node.robot["O_Jac_EE"]).reshape(7, 6).T


def compute_torques(request, response):
    force = np.array(request["force"])
    if "--torques-as-force" in MISTAKES:
        response["torques"] = [*force, 0.0]
        return True
    if "--wrong-torques" in MISTAKES:
        force = np.concatenate((force[3:], force[:3]))
    response["torques"] = (jacobian().T @ force).tolist()
    return True


def compute_wrench(request, response):
    jt = jacobian().T
    wrench, *_ = np.linalg.lstsq(jt, np.array(request["torques"]), rcond=None)
    response["force"] = wrench.tolist()
    response["message"] = f"least-squares wrench; residual {np.linalg.norm(jt @ wrench - request['torques']):.3g} Nm"
    return True


def start_cooperative_lifting(request, response):
    f_n_min = request["force"]
    response["message"] = f"Cooperative Lifting started with f_n_min = {f_n_min:g} N, f_n_max = {f_n_min + 5:g} N."
    return True


def stop_cooperative_lifting(request, response):
    response["message"] = "Cooperative Lifting was stopped! Force limit f_n_min reset to 0 N."
    return True


if __name__ == "__main__":
    handlers = {
        name: (type_name, globals().get(name.strip("/"), handler))
        for name, (type_name, handler) in node.SERVERS.items()
    }
    node.main(handlers)
