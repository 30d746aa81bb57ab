"""Locate the Panda description shipped by the `example-robot-data` wheel (no hard-coded paths)."""

from __future__ import annotations

import importlib.metadata
import os
from functools import cache
from pathlib import Path


@cache
def robot_data_share() -> Path:
    """The `share` folder of example-robot-data (pass it as pinocchio `package_dirs`)."""
    distribution = importlib.metadata.distribution("example-robot-data")
    share = Path(str(distribution.locate_file("cmeel.prefix/share")))
    if not (share / "example-robot-data").is_dir():
        raise FileNotFoundError(f"example-robot-data data not found under {share}")
    return share


def panda_urdf() -> Path:
    """Path of panda.urdf inside the installed example-robot-data wheel."""
    return robot_data_share() / "example-robot-data/robots/panda_description/urdf/panda.urdf"


def mesh_cache() -> Path:
    """Where converted meshes are kept: $HRI_LAB_CACHE, else $XDG_CACHE_HOME/hri-lab, else ~/.cache/hri-lab."""
    if os.environ.get("HRI_LAB_CACHE"):
        return Path(os.environ["HRI_LAB_CACHE"])
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "hri-lab"
