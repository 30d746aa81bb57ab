"""numba's on-disk cache of the compiled kernels, kept true to the sources.

numba caches a compiled function beside its module (`__pycache__/*.nbi, *.nbc`) and checks only
that module's own file: a kernel that calls kernels of other modules (sim/compiled_step.py calls
nearly all of them) would keep running their old code after they change. So the sources of every
module with kernels are hashed together; when the hash differs from the one the cache was built
with, every kernel cache under sim/ is dropped (they compile again, once, at their first call).
`make .venv/.kernels` compiles them all at set-up (`warm_up` in sim/compiled_step.py).
"""
from __future__ import annotations

import hashlib
import os
from pathlib import Path

ROOT = Path(__file__).resolve().parent
KERNEL_MODULES = (  # every module of sim/ with numba kernels (the Makefile's KERNELS lists the same files)
    "compiled_step.py", "signals.py", "spatial.py",
    "controllers/builtin.py", "controllers/lifting_law.py", "controllers/patch.py", "controllers/sp.py",
    "person/human.py", "physics/box.py", "physics/contact.py", "physics/sensor.py",
    "procedures/monitor.py", "robot/cartesian_velocity.py", "robot/panda_kinematics.py",
)


def sources_hash(root: Path = ROOT, modules: tuple[str, ...] = KERNEL_MODULES) -> str:
    digest = hashlib.sha256()
    for name in modules:
        digest.update(name.encode())
        digest.update((root / name).read_bytes())
    return digest.hexdigest()


def drop_stale_caches(root: Path = ROOT, modules: tuple[str, ...] = KERNEL_MODULES) -> bool:
    """Remove the kernel caches under `root` if they were built from other sources of `modules`;
    True if they were removed. A read-only tree is left as it is."""
    stamp = root / "__pycache__" / "kernels.sha256"
    try:
        current = sources_hash(root, modules)
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
