"""A graded submission's limits as one group of processes: a cgroup per trial holding the program
and everything it starts, with a memory cap, a process (and thread) cap and a CPU cap on their sum,
not on each process (a fork does not get a fresh budget).

cgroup v2 when its memory, pids and cpu controllers can be enabled below this process's own group
(a delegated subtree); else cgroup v1's memory, pids and cpu hierarchies (a hybrid host, where those
controllers are bound to v1 and the unified tree has none); else nothing, and the caller says so:
`GroupLimits.statement` names what holds the program. Either needs root (or a delegated subtree).
"""

from __future__ import annotations

import os
import signal
import time
from dataclasses import dataclass
from functools import cache
from pathlib import Path

MIB = 1 << 20
CPU_PERIOD_US = 100_000  # cpu.max's period (the kernel's default)
PREFIX = "hri-lab-"  # the groups made here, below this process's own


@dataclass(frozen=True)
class GroupLimits:
    memory_bytes: int  # every process of the group together: RSS, page cache, its tmpfs files
    pids: int  # processes and threads together
    cpus: float  # CPU time per wall second (1.0: one core)

    def describe(self) -> str:
        return f"memory {self.memory_bytes / MIB:.0f} MiB, {self.pids} processes and threads, {self.cpus:g} CPU"


def _mounts() -> list[tuple[str, str, set[str]]]:
    """(mount point, file system type, super options) of the cgroup file systems."""
    found = []
    for line in Path("/proc/self/mountinfo").read_text().splitlines():
        left, _, right = line.partition(" - ")
        fields, tail = left.split(), right.split()
        if len(tail) >= 3 and tail[0] in ("cgroup", "cgroup2"):
            found.append((fields[4], tail[0], set(tail[2].split(","))))
    return found


def _own_paths() -> dict[str, str]:
    """This process's group in each hierarchy: '' -> its v2 path; a controller's name -> its v1 path."""
    paths = {}
    for line in Path("/proc/self/cgroup").read_text().splitlines():
        _, controllers, path = line.split(":", 2)
        for name in controllers.split(",") if controllers else [""]:
            paths[name] = path
    return paths


def _v2_base() -> tuple[Path | None, str]:
    """The v2 folder new groups go in (controllers enabled for them), or None and why not."""
    mount = next((m for m, kind, _ in _mounts() if kind == "cgroup2"), None)
    if mount is None:
        return None, "no cgroup2 file system"
    own = Path(mount) / _own_paths().get("", "/").lstrip("/")
    missing = {"memory", "pids", "cpu"} - set((own / "cgroup.controllers").read_text().split())
    if missing:
        return None, f"cgroup v2 lacks the {', '.join(sorted(missing))} controller(s) here"
    try:  # a group with processes of its own (not the root) cannot hand controllers to children
        (own / "cgroup.subtree_control").write_text("+memory +pids +cpu")
    except OSError as exc:
        return None, f"cgroup v2 controllers cannot be delegated below {own}: {exc.strerror}"
    return own, ""


def _v1_bases() -> tuple[dict[str, Path] | None, str]:
    """Each v1 controller's folder new groups go in, or None and why not."""
    own = _own_paths()
    bases: dict[str, Path] = {}
    for mount, kind, options in _mounts():
        for controller in ("memory", "pids", "cpu"):
            if kind == "cgroup" and controller in options and controller in own:
                bases[controller] = Path(mount) / own[controller].lstrip("/")
    missing = {"memory", "pids", "cpu"} - set(bases)
    if missing:
        return None, f"no cgroup v1 {', '.join(sorted(missing))} hierarchy"
    return bases, ""


@cache
def cgroup_kind() -> tuple[str | None, str]:
    """("cgroup v2" | "cgroup v1" | None, why not the stronger ones): tried once per process by
    making a group and removing it."""
    reasons: list[str] = []
    for kind in ("cgroup v2", "cgroup v1"):
        try:
            probe = TrialGroup(f"probe-{os.getpid()}", GroupLimits(64 * MIB, 8, 0.5), kind)
            probe.close()
            return kind, "; ".join(reasons)
        except (OSError, GroupUnavailable) as exc:
            reasons.append(str(exc) if isinstance(exc, GroupUnavailable) else f"{kind}: {exc}")
    return None, "; ".join(reasons)


class GroupUnavailable(Exception):
    pass


class TrialGroup:
    """One group (a folder per hierarchy: one in v2, one per controller in v1), its limits written."""

    def __init__(self, name: str, limits: GroupLimits, kind: str) -> None:
        self.limits, self.kind = limits, kind
        self.folders: list[Path] = []
        quota = max(1000, int(limits.cpus * CPU_PERIOD_US))
        if kind == "cgroup v2":
            base, why = _v2_base()
            if base is None:
                raise GroupUnavailable(why)
            folder = self._make(base / f"{PREFIX}{name}")
            self._write(folder / "memory.max", str(limits.memory_bytes))
            if (folder / "memory.swap.max").exists():
                self._write(folder / "memory.swap.max", "0")
            self._write(folder / "pids.max", str(limits.pids))
            self._write(folder / "cpu.max", f"{quota} {CPU_PERIOD_US}")
        else:
            bases, why = _v1_bases()
            if bases is None:
                raise GroupUnavailable(why)
            memory = self._make(bases["memory"] / f"{PREFIX}{name}")
            self._write(memory / "memory.limit_in_bytes", str(limits.memory_bytes))
            if (memory / "memory.memsw.limit_in_bytes").exists():  # swap counted too, when the kernel keeps it
                self._write(memory / "memory.memsw.limit_in_bytes", str(limits.memory_bytes))
            pids = self._make(bases["pids"] / f"{PREFIX}{name}")
            self._write(pids / "pids.max", str(limits.pids))
            cpu = self._make(bases["cpu"] / f"{PREFIX}{name}")
            self._write(cpu / "cpu.cfs_period_us", str(CPU_PERIOD_US))
            self._write(cpu / "cpu.cfs_quota_us", str(quota))

    def _make(self, folder: Path) -> Path:
        try:
            folder.mkdir()
        except FileExistsError:  # a group left by a process that was killed: emptied and reused
            _kill_all(folder)
        self.folders.append(folder)
        return folder

    def _write(self, path: Path, value: str) -> None:
        try:
            path.write_text(value)
        except OSError:
            self.close()
            raise

    def join(self, pid: int = 0) -> None:
        """Move `pid` (0: the calling process) into the group; what it starts later stays there.
        Safe in a child between fork and exec (a preexec_fn)."""
        for folder in self.folders:
            fd = os.open(folder / "cgroup.procs", os.O_WRONLY)
            try:
                os.write(fd, str(pid).encode())
            finally:
                os.close(fd)

    def pids(self) -> list[int]:
        found: set[int] = set()
        for folder in self.folders:
            found |= _procs(folder)
        return sorted(found)

    def memory_peak(self) -> int:
        """The most memory the group held (bytes), as the kernel counted it."""
        for folder in self.folders:
            for name in ("memory.peak", "memory.max_usage_in_bytes"):
                if (folder / name).exists():
                    return int((folder / name).read_text())
        return 0

    def hit(self) -> list[str]:
        """The caps the group ran into (the kernel's counts), in words."""
        hits = []
        for folder in self.folders:
            events = folder / "memory.events"
            if events.exists() and (n := _counter(events.read_text(), "oom_kill")):
                hits.append(f"memory cap: {n} process(es) killed")
            oom = folder / "memory.oom_control"
            if oom.exists() and (n := _counter(oom.read_text(), "oom_kill")):
                hits.append(f"memory cap: {n} process(es) killed")
            pids = folder / "pids.events"
            if pids.exists() and (n := _counter(pids.read_text(), "max")):
                hits.append(f"process cap: {n} fork(s) refused")
        return hits

    def close(self) -> None:
        """Kill what is left in the group and remove it."""
        for folder in reversed(self.folders):
            _kill_all(folder)
            deadline = time.monotonic() + 10.0
            while True:
                try:
                    folder.rmdir()
                    break
                except FileNotFoundError:
                    break
                except OSError:  # its last processes are still being reaped
                    if time.monotonic() > deadline:
                        break
                    _kill_all(folder)
                    time.sleep(0.02)
        self.folders = []

    def statement(self) -> str:
        return f"{self.limits.describe()} for the program and all it starts ({self.kind}, one group per trial)"


def _counter(text: str, key: str) -> int:
    for line in text.splitlines():
        name, _, value = line.partition(" ")
        if name == key:
            return int(value)
    return 0


def _procs(folder: Path) -> set[int]:
    try:
        return {int(p) for p in (folder / "cgroup.procs").read_text().split()}
    except OSError:
        return set()


def _kill_all(folder: Path) -> None:
    """SIGKILL every process in the folder's group (v2: cgroup.kill, at once; v1: until none is left,
    a fork racing the kill is caught by the next round)."""
    if (folder / "cgroup.kill").exists():
        try:
            (folder / "cgroup.kill").write_text("1")
        except OSError:
            pass
    for _ in range(100):
        left = _procs(folder) - {os.getpid()}
        if not left:
            return
        for pid in left:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        time.sleep(0.01)
