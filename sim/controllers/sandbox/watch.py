"""The child seen from outside: its processes and threads, CPU time and context switches (/proc),
the CPU it is kept on, reaping it and saying why it ended."""

from __future__ import annotations

import ctypes
import os
import signal
import time

_LIBC = ctypes.CDLL(None, use_errno=True)


def current_cpu() -> int | None:
    """The CPU the calling thread runs on now (glibc's sched_getcpu), None if unknown."""
    try:
        cpu = _LIBC.sched_getcpu()
    except AttributeError:
        return None
    return cpu if cpu >= 0 else None


def process_tree(pid: int | None) -> list[int]:
    """pid and every process below it (/proc/PID/task/TID/children)."""
    if pid is None:
        return []
    pids, queue = [], [pid]
    while queue:
        pid = queue.pop()
        pids.append(pid)
        try:
            for tid in os.listdir(f"/proc/{pid}/task"):
                with open(f"/proc/{pid}/task/{tid}/children") as handle:
                    queue += [int(c) for c in handle.read().split()]
        except OSError:
            pass
    return pids


def _summed(pids: list[int], read) -> float:
    """read(pid) summed over pids; one that ended meanwhile (its /proc entry gone or cut short) counts 0."""
    total = 0
    for pid in pids:
        try:
            total += read(pid)
        except (OSError, IndexError, ValueError):
            pass
    return total


def count_tasks(pids: list[int]) -> int:
    """Threads of the processes pids."""
    return int(_summed(pids, lambda pid: len(os.listdir(f"/proc/{pid}/task"))))


def voluntary_switches(pids: list[int]) -> int:
    """The processes' voluntary context switches (/proc/PID/status)."""

    def switches(pid: int) -> int:
        with open(f"/proc/{pid}/status") as handle:
            return sum(int(line.split()[1]) for line in handle if line.startswith("voluntary_ctxt_switches"))

    return int(_summed(pids, switches))


def cpu_time(pids: list[int]) -> float:
    """s of CPU used by the processes (all threads): utime + stime from /proc."""

    def ticks(pid: int) -> int:
        with open(f"/proc/{pid}/stat") as handle:
            rest = handle.read().rpartition(")")[2].split()
        return int(rest[11]) + int(rest[12])

    return _summed(pids, ticks) / os.sysconf("SC_CLK_TCK")


def scheduled_time(pids: list[int]) -> float | None:
    """s the processes ran or waited for a CPU (/proc/PID/schedstat: time on a CPU + time runnable
    on a run queue); what is left of their wall time they slept or blocked. None where the kernel
    keeps no schedstat."""
    if not os.path.exists("/proc/self/schedstat"):
        return None

    def scheduled(pid: int) -> int:
        with open(f"/proc/{pid}/schedstat") as handle:
            on_cpu, waiting = handle.read().split()[:2]
        return int(on_cpu) + int(waiting)

    return _summed(pids, scheduled) / 1e9


def own_run_delay() -> float:
    """s the calling thread waited runnable for a CPU (/proc/thread-self/schedstat); 0 if unknown."""
    try:
        with open("/proc/thread-self/schedstat") as handle:
            return int(handle.read().split()[1]) / 1e9
    except (OSError, IndexError, ValueError):
        return 0.0


def stat_ticks(line: str) -> tuple[int, int]:
    """(busy, all) clock ticks of a `cpu` line of /proc/stat: busy is all but idle and iowait (steal,
    the hypervisor's other guests, counts as busy: it is not ours either); guest time, inside user's
    already, is not counted twice."""
    ticks = [int(x) for x in line.split()[1:9]]
    return sum(ticks) - ticks[3] - ticks[4], sum(ticks)


def cpu_busy_time(cpu: int) -> float:
    """s CPU `cpu` has been busy since boot, whatever ran (`stat_ticks`); 0 if unknown."""
    try:
        with open("/proc/stat") as handle:
            for line in handle:
                if line.startswith(f"cpu{cpu} "):
                    return stat_ticks(line)[0] / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError):
        pass
    return 0.0


def own_cpu_time() -> float:
    """s of CPU the calling thread has used (/proc/thread-self/stat, utime + stime); 0 if unknown."""
    try:
        with open("/proc/thread-self/stat") as handle:
            rest = handle.read().rpartition(")")[2].split()
        return (int(rest[11]) + int(rest[12])) / os.sysconf("SC_CLK_TCK")
    except (OSError, IndexError, ValueError):
        return 0.0


def keep_on_cpu(pids: list[int], cpus: set[int]) -> None:
    """Let the processes run on `cpus` only (pid 0: the calling thread)."""
    for pid in pids:
        try:
            os.sched_setaffinity(pid, cpus)
        except OSError:  # gone, or not allowed here: it runs where the scheduler puts it
            pass


def reap(pid: int, grace: float) -> int | None:
    """Wait up to `grace` s for the child to exit, then SIGKILL its process group; its wait status."""
    end = time.perf_counter() + grace
    while True:
        try:
            done, status = os.waitpid(pid, os.WNOHANG)
        except ChildProcessError:
            return None
        if done:
            return status
        if time.perf_counter() > end:
            try:
                os.killpg(pid, signal.SIGKILL)
            except OSError:
                pass
            try:
                return os.waitpid(pid, 0)[1]
            except ChildProcessError:
                return None
        time.sleep(0.005)


def why_ended(status: int | None) -> str:
    """A wait status in words (its exit code or signal, with what the signal usually means here)."""
    if status is None:
        return "the controller's process is gone"
    if os.WIFSIGNALED(status):
        sig = os.WTERMSIG(status)
        hint = {
            signal.SIGXCPU: " (CPU-time limit)",
            signal.SIGKILL: " (killed: memory or time limit)",
            signal.SIGSEGV: " (a crash)",
        }.get(signal.Signals(sig), "")
        return f"the controller's process was killed by {signal.Signals(sig).name}{hint}"
    return f"the controller's process exited with code {os.WEXITSTATUS(status)} (os._exit or sys.exit)"
