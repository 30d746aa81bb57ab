"""The lab's built-in lifting controllers, by name: the one table the start service, the
`controller` parameter, the CLI and the comparison use."""

from __future__ import annotations

from dataclasses import dataclass

from sim.controllers.interface import Controller
from sim.controllers.patch import PatchController
from sim.controllers.sp import SPController

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
