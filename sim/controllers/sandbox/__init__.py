"""A student's controller in a process of its own, under bubblewrap: the Controller protocol
(reset/step/start/stop) answered by a child process the student's code cannot climb out of.

One idea per module:
    budget.py  SandboxBudget: what a sandboxed controller may use
    wire.py    the messages between the two ends (what crosses the boundary, byte for byte)
    jail.py    the bubblewrap command line, the child's environment, whether bwrap runs here
    zygote.py  the jail's first process: imports once, clears the jail and forks a child per item
    pool.py    the parent's jails (one per file, process and thread), ended when idle or at exit
    watch.py   the child seen from outside: its processes and threads, CPU time and context
               switches (/proc), its CPU affinity, reaping it and saying why it died
    parent.py  SandboxedController: the grader's / the world's end
    child.py   what runs in a forked child: limits, then the student's class served over the wire;
               it imports only wire.py and the interface

The names other code uses are importable from here (`from sim.controllers.sandbox import
SandboxedController, SandboxBudget, sandbox_unavailable`); they are loaded on first use, so that
the child, which imports this package too, loads nothing of the parent's side.
"""

from __future__ import annotations

import importlib

_EXPORTS = {
    "SandboxBudget": "budget",
    "SandboxedController": "parent",
    "sandbox_unavailable": "jail",
    "bwrap_command": "jail",
    "CHILD_ENV": "jail",
    "current_cpu": "watch",
}
__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f"{__name__}.{_EXPORTS[name]}"), name)
