"""--controller sp|patch|FILE.py[:Class] of `experiment` and `serve`."""

from __future__ import annotations

import sys

from sim.controllers.plugin import PluginError, controller_factory


def loaded_factory(spec: str | None, sandboxed: bool = True):
    """sp, patch or a plug-in file's factory, a plug-in loaded once here (in its sandbox) so that
    a broken file stops the command now, with its reason (exit 2), not at the first trial."""
    try:
        factory = controller_factory(spec, sandboxed)
        getattr(factory(), "close", lambda: None)()
    except PluginError as exc:
        print(f"hri-lab: controller: {exc}", file=sys.stderr)
        raise SystemExit(2) from None
    return factory
