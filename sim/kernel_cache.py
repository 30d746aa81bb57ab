"""numba's on-disk cache of the compiled kernels, kept true to the sources.

numba caches a compiled function beside its module (`__pycache__/*.nbi, *.nbc`) and checks only
that module's own file: a kernel that calls kernels of other modules (sim/compiled_step.py calls
nearly all of them), or reads their constants (the state layouts), would keep running their old
code after they change. So every source of sim/ is hashed; when the hash differs from the one the
caches were built with, every kernel cache under sim/ is dropped (they compile again, once, at
their first call). `make .venv/.kernels` compiles them all at set-up (sim/warm_up.py), again
whenever a file of sim/ changed.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

ROOT = Path(__file__).resolve().parent


def sources_hash(root: Path = ROOT) -> str:
    """sha256 of every .py file under `root` (names and contents)."""
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        digest.update(str(path.relative_to(root)).encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


def drop_stale_caches(root: Path = ROOT) -> bool:
    """Remove the kernel caches under `root` if they were built from other sources; True if they
    were removed. A read-only tree is left as it is."""
    stamp = root / "__pycache__" / "kernels.sha256"
    try:
        current = sources_hash(root)
        if stamp.read_text() == current:
            return False
    except OSError:
        pass
    try:
        for path in root.rglob("__pycache__/*.nb[ic]"):
            path.unlink(missing_ok=True)
        stamp.parent.mkdir(exist_ok=True)
        temporary = stamp.with_name(f"{stamp.name}.{os.getpid()}")
        temporary.write_text(current)
        os.replace(temporary, stamp)  # atomic: parallel processes agree
    except OSError:
        return False
    return True
