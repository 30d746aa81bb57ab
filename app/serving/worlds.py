"""The worlds a lab can serve (`hri-lab serve --world NAME`): the one place that names them. A new
world is a package declaring its World (app/worlds/contract.py) and one line here (docs/design.md,
"Adding a world")."""

from __future__ import annotations

from app.lab.world import LIFTING
from app.mobile.world import MOBILE
from app.worlds.contract import World

WORLDS: dict[str, World] = {world.name: world for world in (LIFTING, MOBILE)}
DEFAULT = next(iter(WORLDS))  # what `serve` serves unless --world names another: the first registered
