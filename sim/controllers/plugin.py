"""Load a student's controller from a file: `path/to/file.py[:ClassName]` (default class
`CooperativeLifting`, as in the template). Loading happens only from the command line or a
config file, never through the API. The class is instantiated with no argument and must have
`reset()` and `step(wrench_ee, transform_ee_to_base, params, dt)`; it may also have
`start(params, force) -> str` and `stop(params) -> str`, the handlers of the start/stop services.
The file is never imported here: it runs in a sandboxed process (sim/controllers/sandbox/).
"""

from __future__ import annotations

import codecs
import copy
from dataclasses import dataclass, replace
from pathlib import Path

from sim.controllers.interface import ControllerFault
from sim.controllers.sandbox import SandboxBudget, SandboxedController

DEFAULT_CLASS = "CooperativeLifting"


def controller_factory(spec: str | None, sandboxed: bool = True):
    """`sp`, `patch` (in-process) or `FILE.py[:Class]` (a sandboxed plug-in) -> a factory of new controllers."""
    # imported here: the built-ins load numba's kernels (~1.3 s of CPU), which a command that only
    # loads or prints a plug-in file (`hri-lab template`, `grade`'s parent) does not need
    from sim.controllers.builtin import BUILTIN, BuiltinFactory

    if spec is None or spec in BUILTIN:
        return BuiltinFactory(spec or "sp")
    return PluginFactory(spec, sandboxed=sandboxed)


class PluginError(Exception):
    """The plug-in cannot be loaded (the message says why)."""


def split_spec(spec: str) -> tuple[Path, str]:
    """`file.py:Name` -> (file.py, Name); `file.py` -> (file.py, DEFAULT_CLASS)."""
    head, sep, tail = spec.rpartition(":")
    if sep and tail.isidentifier():
        return Path(head), tail
    return Path(spec), DEFAULT_CLASS


def check_file(path: Path) -> None:
    """PluginError saying what `path` is when it cannot be a controller file: missing, a folder, or
    not Python source text (binary: e.g. a recording or a compiled file handed by mistake)."""
    if path.is_dir():
        raise PluginError(
            f"{path} is a folder, not a controller file: name the .py file in it "
            "(`hri-lab grade` takes folders of them)"
        )
    if not path.is_file():
        raise PluginError(f"no controller file {path}")
    with open(path, "rb") as f:
        head = f.read(65536)
    try:
        codecs.getincrementaldecoder("utf-8")().decode(head)  # a character cut at the end is text too
        binary = b"\0" in head
    except UnicodeDecodeError:
        binary = True
    if binary:
        raise PluginError(
            f"{path} is not a Python file (binary, not source text): a controller is a .py file "
            f"with a class {DEFAULT_CLASS} (start from `hri-lab template`)"
        )


@dataclass(frozen=True)
class PluginFactory:
    """A picklable factory (trials may run in other processes): each call starts the file's class
    in a sandboxed process of its own (sim/controllers/sandbox/) and returns its controller;
    `sandboxed=False` (`--unsandboxed`) drops bubblewrap but keeps the process and its limits."""

    spec: str
    budget: SandboxBudget = SandboxBudget()
    sandboxed: bool = True
    eager: bool = True  # load now (False: at the first call, in the process that steps it)
    carried: SandboxedController | None = None  # the file read where the factory was made (carrying())
    # a file without start()/stop(): the lab's handlers stand in (the live lab), or none (a grade: the
    # handlers are part of the exercise, and a missing one scores as one that does nothing)
    stand_in: bool = True

    def carrying(self) -> PluginFactory:
        """This factory with the file's text read now and carried along: it makes the same
        controllers on a machine that has no copy of the file (a Dask worker). PluginError when
        the file cannot be a controller file (check_file)."""
        path, name = split_spec(self.spec)
        check_file(path)
        return replace(self, carried=SandboxedController(path, name, self.budget, self.sandboxed))

    def __call__(self) -> SandboxedController:
        path, name = split_spec(self.spec)
        if self.carried is not None:  # a copy starts a child of its own (SandboxedController.__getstate__)
            controller = copy.copy(self.carried)
        else:
            check_file(path)
            controller = SandboxedController(path, name, self.budget, self.sandboxed)
        controller.stand_in = self.stand_in
        if self.eager:
            try:
                controller.load()
            except ControllerFault as fault:
                raise PluginError(str(fault)) from None
        return controller


def template_path() -> Path:
    """The controller plug-in's starting file (sim/controllers/template.py): what `hri-lab template`
    prints, and the boilerplate of the similarity report (every student's file is built on it)."""
    return Path(__file__).with_name("template.py")
