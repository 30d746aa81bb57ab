"""How many live labs one machine holds (a JupyterHub node's size): N labs started as the hub starts
them (`hri-lab serve --port P --world lifting`, each on a free port, as jupyter-server-proxy does), each
with cooperative lifting running (the scripted participant, /services/start_cooperative_lifting), its
dashboard's data read as the page reads it (the five topic streams of static/app.js at the page's
rates, its polls at theirs), and one student node streaming F_ext into a rospy callback
(bench/ros_fext_subscriber.py under `hri-lab run`). For N = 1, 2, 4, 8, ... it prints each lab's
real-time factor, its missed 1 kHz periods (/health's overruns: periods the loop skipped) and
lateness p99, the CPU (% of one core) and memory (PSS, MiB) of the lab's processes and of the node's,
and stops once the machine falls behind (a lab under MIN_RTF, or missing more than MAX_MISSED_SHARE
of its periods).

The dashboards' readers run in this process: in a course they are the students' browsers, elsewhere.
The 3D view (viser) is served but not opened (a browser's WebGL tab would add its own cost).

    .venv/bin/python -m bench.lab_density [--max-labs 16] [--measure 20] [--warm-up 8] [--realtime] [--all]

--realtime keeps CAP_SYS_NICE (the loop then runs SCHED_FIFO, app/runtime/loop.py); by default the
labs run without it, as in a Kubernetes pod (the loop then runs at normal priority)."""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import shutil
import subprocess
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path

import httpx

from app.serving.launch import ServerProcess, stop_group

ROOT = Path(__file__).resolve().parent.parent
SUBSCRIBER = Path(__file__).resolve().parent / "ros_fext_subscriber.py"
MIN_RTF = 0.95  # a lab slower than this has fallen behind
MAX_MISSED_SHARE = 0.01  # of its 1 kHz periods
PERIOD_S = 1e-3  # the loop's period (1 kHz)
# what the dashboard page reads (static/app.js): topic streams at their rates (Hz), polls (s)
PAGE_STREAMS = {
    "/lifting_state": 10,
    "/franka_state_controller/F_ext": 20,
    "/cartesian_velocity_controller/command": 20,
    "/trial": 4,
    "/contact_state": 20,
}
PAGE_POLLS = {  # each page's timers: the console (the lines after the newest it has), the cv2 windows, pollSlow's reads
    "/log": 1.0,
    "/camera/windows": 1.0,
    "/health": 2.0,
    "/params/cooperative_lifting/controller": 2.0,
    "/params/cooperative_lifting/alpha": 2.0,
    "/services": 2.0,
    "/actions": 2.0,
}
PAGE_READS_ONCE = {"/params", "/topics", "/view", "/params/human/profile", "/params/human/profile/describe"}
CLOCK_TICKS = os.sysconf("SC_CLK_TCK")


# --- pure parts (tests/bench/test_lab_density.py) -------------------------------------------------
def doublings(limit: int) -> list[int]:
    """1, 2, 4, ... up to limit (limit itself last if it is not a power of two)."""
    counts, n = [], 1
    while n < limit:
        counts.append(n)
        n *= 2
    return counts + [limit]


def cpu_ticks(stat_text: str) -> int:
    """utime + stime (clock ticks) from a /proc/PID/stat line (the command may hold spaces and ')')."""
    fields = stat_text[stat_text.rindex(")") + 2 :].split()
    return int(fields[11]) + int(fields[12])  # fields 14 and 15 of proc(5), counted from the state (3)


def parent_pid(stat_text: str) -> int:
    return int(stat_text[stat_text.rindex(")") + 2 :].split()[1])


def descendants(root: int, parents: dict[int, int]) -> set[int]:
    """root and every process below it, from a {pid: parent pid} map."""
    children: dict[int, list[int]] = {}
    for pid, parent in parents.items():
        children.setdefault(parent, []).append(pid)
    found, todo = set(), [root]
    while todo:
        pid = todo.pop()
        if pid not in found:
            found.add(pid)
            todo.extend(children.get(pid, []))
    return found


def pss_kib(smaps_rollup: str) -> int:
    """The proportional set size (KiB: shared pages split between their users) of /proc/PID/smaps_rollup."""
    for line in smaps_rollup.splitlines():
        if line.startswith("Pss:"):
            return int(line.split()[1])
    return 0


@dataclass
class LabFigures:
    """One lab over the measured span."""

    rtf: float  # simulation s per wall s
    missed: int  # 1 kHz periods the loop skipped (overruns)
    periods: int  # periods of the span (simulation time / 1 ms)
    lateness_p99_ms: float
    lab_cpu: float  # % of one core, the lab's processes
    lab_mib: float  # PSS
    node_cpu: float
    node_mib: float
    realtime: bool  # the loop runs SCHED_FIFO
    fext_handled: float | None = None  # share of F_ext's messages the node's callback handled

    @property
    def missed_share(self) -> float:
        return self.missed / self.periods if self.periods else 1.0

    def behind(self) -> bool:
        return self.rtf < MIN_RTF or self.missed_share > MAX_MISSED_SHARE


def lab_figures(
    health_0: dict, health_1: dict, wall_s: float, ticks: tuple[int, int], node_ticks: tuple[int, int], **rest
) -> LabFigures:
    """A lab's figures from /health at the span's two ends, the wall time between them and the CPU
    clock ticks (at both ends) of the lab's and the node's processes."""
    sim_s = health_1["sim_time"] - health_0["sim_time"]
    return LabFigures(
        rtf=sim_s / wall_s,
        missed=health_1["overruns"] - health_0["overruns"],
        periods=round(sim_s / PERIOD_S),
        lateness_p99_ms=health_1["lateness_p99_ms"],
        lab_cpu=100.0 * (ticks[1] - ticks[0]) / CLOCK_TICKS / wall_s,
        node_cpu=100.0 * (node_ticks[1] - node_ticks[0]) / CLOCK_TICKS / wall_s,
        realtime=bool(health_1["realtime_priority"]),
        **rest,
    )


def row(n: int, i: int, f: LabFigures) -> str:
    handled = "-" if f.fext_handled is None else f"{100 * f.fext_handled:.0f} %"
    return (
        f"{n:>3} {i:>3} {f.rtf:6.3f} {f.missed:>7} {100 * f.missed_share:7.2f} % {f.lateness_p99_ms:8.2f}"
        f" {f.lab_cpu:7.1f} {f.lab_mib:7.0f} {f.node_cpu:7.1f} {f.node_mib:7.0f} {handled:>6}"
        f" {'FIFO' if f.realtime else 'normal':>6}"
    )


HEADER = (
    "  N lab    RTF  missed  missed %  p99 ms  lab CPU% lab MiB node CPU% node MiB F_ext  prio\n"
    "  (RTF: simulation s per wall s; missed: 1 kHz periods skipped; CPU: % of one core; MiB: PSS)"
)


def summary(n: int, figures: list[LabFigures]) -> dict:
    """The per-student figures of one N: the means (a pod holds the lab and the student's node)."""
    return {
        "labs": n,
        "rtf_min": min(f.rtf for f in figures),
        "missed_share_max": max(f.missed_share for f in figures),
        "cpu_per_student": sum(f.lab_cpu + f.node_cpu for f in figures) / n,
        "mib_per_student": sum(f.lab_mib + f.node_mib for f in figures) / n,
        "behind": any(f.behind() for f in figures),
    }


# --- the machine's side ---------------------------------------------------------------------------
def _read(path: str) -> str:
    try:
        return Path(path).read_text()
    except OSError:
        return ""


def process_tree(root: int) -> set[int]:
    parents = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit() and (text := _read(f"/proc/{entry}/stat")):
            parents[int(entry)] = parent_pid(text)
    return descendants(root, parents)


def tree_ticks(pids: set[int]) -> int:
    return sum(cpu_ticks(text) for pid in pids if (text := _read(f"/proc/{pid}/stat")))


def tree_mib(pids: set[int]) -> float:
    return sum(pss_kib(_read(f"/proc/{pid}/smaps_rollup")) for pid in pids) / 1024


class Dashboards:
    """The pages' reading of every lab, in one thread of this process (the students' browsers)."""

    def __init__(self) -> None:
        self.loop = asyncio.new_event_loop()
        self.messages = 0
        self._tasks: list[asyncio.Task] = []
        threading.Thread(target=self.loop.run_forever, daemon=True).start()

    def open(self, url: str) -> None:
        asyncio.run_coroutine_threadsafe(self._open(url), self.loop).result(timeout=30)

    async def _open(self, url: str) -> None:
        ws = url.replace("http", "ws", 1)
        for name, rate in PAGE_STREAMS.items():
            self._tasks.append(asyncio.create_task(self._stream(f"{ws}/topics{name}/stream?rate={rate}")))
        for path, every in PAGE_POLLS.items():
            self._tasks.append(asyncio.create_task(self._poll(url + path, every)))

    async def _stream(self, url: str) -> None:
        import websockets

        while True:
            try:
                async with websockets.connect(url, max_size=None) as socket:
                    async for _ in socket:
                        self.messages += 1
            except (OSError, websockets.WebSocketException):
                await asyncio.sleep(2.0)  # as the page: reconnect after 2 s

    async def _poll(self, url: str, every: float) -> None:
        seen = 0  # the console's newest line: it asks for those after it, as the page does
        async with httpx.AsyncClient(timeout=10) as http:
            while True:
                try:
                    if url.endswith("/log"):
                        lines = (await http.get(url, params={"after_seq": seen})).json()
                        seen = max([seen, *(line["seq"] for line in lines)])
                    else:
                        await http.get(url)
                except (httpx.HTTPError, ValueError, TypeError, KeyError):
                    pass
                await asyncio.sleep(every)

    def close(self) -> None:
        for task in self._tasks:
            self.loop.call_soon_threadsafe(task.cancel)
        self._tasks.clear()


class Student:
    """One lab (as the hub starts it), its lifting, its dashboard and its F_ext node."""

    def __init__(self, dashboards: Dashboards) -> None:
        self.lab = ServerProcess("--world", "lifting", timeout=300.0, own_session=True)
        answer = httpx.post(f"{self.lab.url}/services/start_cooperative_lifting", json={"force": 10}, timeout=30)
        answer.raise_for_status()
        dashboards.open(self.lab.url)
        self.node: subprocess.Popen | None = None

    def start_node(self, seconds: float) -> None:
        """The student's node, for `seconds` (started once every lab is up: it outlasts the span)."""
        self.node = subprocess.Popen(
            [sys.executable, "-m", "app.cli", "run", "--url", self.lab.url, str(SUBSCRIBER), str(seconds)],
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            text=True,
            cwd=ROOT,
            start_new_session=True,
        )

    def health(self) -> dict:
        return httpx.get(f"{self.lab.url}/health", timeout=30).json()

    def fext_handled(self, timeout_s: float) -> float | None:
        assert self.node is not None  # started by start_node
        try:
            out, _ = self.node.communicate(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            return None
        for line in reversed(out.splitlines()):
            if line.startswith("{"):
                figures = json.loads(line)
                return figures["handled"] / figures["published"] if figures["published"] else None
        return None

    def stop(self) -> None:
        if self.node is not None:
            stop_group(self.node, 5.0)
        stop_group(self.lab.proc, 10.0)
        self.lab.stop()


def measure(n: int, warm_up_s: float, measure_s: float) -> list[LabFigures]:
    dashboards = Dashboards()
    students: list[Student] = []
    try:
        for _ in range(n):
            students.append(Student(dashboards))
        for s in students:
            s.start_node(warm_up_s + measure_s + 5.0)
        time.sleep(warm_up_s)  # the nodes connect, the streams settle (a span, not a condition: a bench)
        trees = [(process_tree(s.lab.proc.pid), process_tree(s.node.pid)) for s in students if s.node]
        start = [(s.health(), tree_ticks(lab), tree_ticks(node)) for s, (lab, node) in zip(students, trees)]
        t0 = time.monotonic()
        time.sleep(measure_s)
        wall = time.monotonic() - t0
        end = [(s.health(), tree_ticks(lab), tree_ticks(node)) for s, (lab, node) in zip(students, trees)]
        memory = [(tree_mib(lab), tree_mib(node)) for lab, node in trees]
        figures = []
        for (h0, l0, n0), (h1, l1, n1), (lab_mib, node_mib) in zip(start, end, memory):
            figures.append(lab_figures(h0, h1, wall, (l0, l1), (n0, n1), lab_mib=lab_mib, node_mib=node_mib))
        for s, f in zip(students, figures):
            f.fext_handled = s.fext_handled(timeout_s=30.0 + 5.0 * n)
        return figures
    finally:
        dashboards.close()
        for s in students:
            s.stop()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max-labs", type=int, default=16)
    parser.add_argument("--warm-up", type=float, default=8.0, help="s between the last start and the span")
    parser.add_argument("--measure", type=float, default=20.0, help="s measured")
    parser.add_argument("--realtime", action="store_true", help="keep CAP_SYS_NICE (SCHED_FIFO loops)")
    parser.add_argument("--json", help="also write the summaries to this file")
    parser.add_argument(
        "--all", action="store_true", help="go on to --max-labs after the machine fell behind (a busy machine)"
    )
    args = parser.parse_args()
    if not args.realtime and os.geteuid() == 0 and "HRI_LAB_DENSITY_CHILD" not in os.environ:
        # as root, the labs could take SCHED_FIFO: run this bench again without CAP_SYS_NICE, as a pod
        setpriv = shutil.which("setpriv")
        if setpriv is None:
            raise SystemExit("setpriv (util-linux) is needed to drop CAP_SYS_NICE; or pass --realtime")
        env = {**os.environ, "HRI_LAB_DENSITY_CHILD": "1"}
        command = [
            setpriv,
            "--inh-caps=-sys_nice",
            "--bounding-set=-sys_nice",
            sys.executable,
            "-m",
            "bench.lab_density",
        ]
        raise SystemExit(subprocess.call([*command, *sys.argv[1:]], env=env, cwd=ROOT))
    print(f"machine: {os.cpu_count()} CPUs, load average {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    print(HEADER, flush=True)
    summaries = []
    for n in doublings(args.max_labs):
        figures = measure(n, args.warm_up, args.measure)
        for i, f in enumerate(figures):
            print(row(n, i, f), flush=True)
        summaries.append(summary(n, figures))
        s = summaries[-1]
        print(
            f"N={n}: min RTF {s['rtf_min']:.3f}, max missed {100 * s['missed_share_max']:.2f} %, per student "
            f"{s['cpu_per_student']:.0f} % of a core, {s['mib_per_student']:.0f} MiB; load average "
            f"{os.getloadavg()[0]:.2f}" + ("  <- the machine fell behind" if s["behind"] else ""),
            flush=True,
        )
        if s["behind"] and not args.all:
            break
    if args.json:
        Path(args.json).write_text(json.dumps(summaries, indent=1))


if __name__ == "__main__":
    main()
