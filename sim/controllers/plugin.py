"""Load a student's controller from a file: `path/to/file.py[:ClassName]` (default class
`CooperativeLifting`, as in the template). Loading happens only from the command line or a
config file, never through the API. The class is instantiated with no argument and must have
`reset()` and `step(wrench_ee, transform_ee_to_base, params, dt)`; it may also have
`start(params, force) -> str` and `stop(params) -> str`, the handlers of the start/stop services.
"""
from __future__ import annotations

import hashlib
import importlib.util
import sys
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from sim.controllers.builtin import BUILTIN, BuiltinFactory
from sim.controllers.guard import Budget, GuardedController

DEFAULT_CLASS = "CooperativeLifting"


def controller_factory(spec: str | None):
    """`sp`, `patch` or `FILE.py[:Class]` (a guarded plug-in) -> a factory of new controllers."""
    if spec is None or spec in BUILTIN:
        return BuiltinFactory(spec or "sp")
    return PluginFactory(spec)


class PluginError(Exception):
    """The plug-in cannot be loaded (the message says why)."""


def split_spec(spec: str) -> tuple[Path, str]:
    """`file.py:Name` -> (file.py, Name); `file.py` -> (file.py, DEFAULT_CLASS)."""
    head, sep, tail = spec.rpartition(":")
    if sep and tail.isidentifier():
        return Path(head), tail
    return Path(spec), DEFAULT_CLASS


@lru_cache(maxsize=None)
def load_class(spec: str) -> type:
    """The controller class of a plug-in file (imported once per process)."""
    path, name = split_spec(spec)
    if not path.is_file():
        raise PluginError(f"no controller file {path}")
    module_name = "hri_lab_plugin_" + hashlib.sha1(str(path.resolve()).encode()).hexdigest()[:12]
    module_spec = importlib.util.spec_from_file_location(module_name, path)
    module = importlib.util.module_from_spec(module_spec)
    sys.modules[module_name] = module
    try:
        module_spec.loader.exec_module(module)
    except Exception as exc:  # noqa: BLE001 - a broken file is reported, not a crash
        raise PluginError(f"importing {path} failed: {type(exc).__name__}: {exc}") from None
    cls = getattr(module, name, None)
    if not isinstance(cls, type):
        raise PluginError(f"{path} has no class {name} (give another with {path}:ClassName)")
    for method in ("reset", "step"):
        if not callable(getattr(cls, method, None)):
            raise PluginError(f"{name} in {path} has no {method}() method")
    return cls


@dataclass(frozen=True)
class PluginFactory:
    """A picklable factory (trials may run in other processes): each call loads the file's class
    (once per process) and returns a new guarded instance."""

    spec: str
    budget: Budget = Budget()

    def __call__(self) -> GuardedController:
        try:
            instance = load_class(self.spec)()
        except PluginError:
            raise
        except Exception as exc:  # noqa: BLE001
            raise PluginError(f"creating the controller failed: {type(exc).__name__}: {exc}") from None
        return GuardedController(instance, self.budget)
