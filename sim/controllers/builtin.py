"""The lab's built-in lifting controllers, by name: the one table the start service, the
`controller` parameter, the CLI and the comparison use."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from sim.controllers.interface import RUNNING, Controller
from sim.controllers.lifting_law import PATCH, low_pass, to_base_rate_limited
from sim.controllers.patch import PatchController, patch_twist_ee
from sim.controllers.sp import SPController, sp_twist_ee

CONTROLLERS: dict[str, type] = {"sp": SPController, "patch": PatchController}
BUILTIN = tuple(CONTROLLERS)  # the names: ("sp", "patch")


def builtin(name: str) -> Controller:
    """A new built-in controller: "sp" (Single Point) or "patch" (patch-aware)."""
    return CONTROLLERS[name]()


def builtin_name(controller: Controller) -> str | None:
    """The name of a built-in controller; None for anything else (a plug-in)."""
    return next((name for name, cls in CONTROLLERS.items() if type(controller) is cls), None)


@dataclass(frozen=True)
class BuiltinFactory:
    """A picklable factory of a built-in controller."""

    name: str

    def __call__(self) -> Controller:
        return builtin(self.name)


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
