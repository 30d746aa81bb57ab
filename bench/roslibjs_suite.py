"""roslibjs's own tests that talk to a ROS system (its `test/examples/*.js` and
`test/service.test.js`, unchanged; the latter imports the package built, so its `dist/` is built
first when the checkout has none) against the lab: issue 31's measure of a JavaScript client
nobody here wrote (docs/ros-programs.md).

The tests connect to `ws://localhost:9090` (hard-coded in them), so this starts `hri-lab serve
--port 9090 --exercises` (port 9090 must be free), then the nodes roslibjs's setup
(test/examples/setup_examples.launch) starts, as programs under `hri-lab run`:

| roslibjs's setup | here |
|---|---|
| actionlib_tutorials `fibonacci_server` (C++) | bench/roslibjs_nodes/fibonacci_server.py (the same sequence; the tutorial's Python server gives one number fewer), with ros/common_tutorials' actionlib_tutorials messages |
| rospy_tutorials `add_two_ints_server` | `rospy_tutorials/005_add_two_ints/add_two_ints_server` of ros/ros_tutorials (the corpus) |
| `rostopic pub /listener std_msgs/String "Hello, World"` | bench/roslibjs_nodes/hello_world_publisher.py |
| tf `static_transform_publisher 0 0 0 0 0 0 /world /turtle1 100` | bench/roslibjs_nodes/static_transform_publisher.py, same arguments |
| `tf2_web_republisher` | the lab's own (`/republish_tfs`, the `tf2_web_republisher` action) |

then runs roslibjs's vitest on those files in the checkout and prints passed/failed per test (the
first line of a failure's message) and the count. roslibjs is not part of this repository: fetch it
into a folder of its own and install its development dependencies there first:

    (cd ROSLIBJS && npm ci --ignore-scripts)
    .venv/bin/python -m bench.roslibjs_suite ROSLIBJS --corpus /work/corpus [--lab /work/wt/OTHER]

On a shared machine, `--own-network` (as root) runs it all in a network namespace of its own, where
port 9090 is free whoever else uses it.
"""

from __future__ import annotations

import argparse
import json
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path

from bench.ros_corpus import ROOT, Lab, Process, find_checkouts, serving, stop_on_sigterm

PORT = 9090  # the tests' own
# the files that talk to ws://localhost:9090 (test/service.test.js imports the built package, dist/: built
# first, as the package's `prepare` script does, when the checkout has none)
TESTS = ("test/examples", "test/service.test.js")
NODES = Path(__file__).with_name("roslibjs_nodes")
SUITE_TIMEOUT_S = 900.0  # a bound for a hung suite, not a speed figure
SETUP_S = 60.0  # for the setup's programs to be up (as setup_examples.bash waits for /listener)

COMMON_TUTORIALS = ("ros/common_tutorials", "b3a86ff8a60efd678f942deab47efcadd52a5336")
ROS_TUTORIALS = ("ros/ros_tutorials", "db6328879831b4abadac939bd69b43133414c0db")
# the setup's nodes: (a corpus checkout and a path in it, or None and a path here), their arguments, and
# the corpus checkout that is their workspace (their interface packages), if they need one
SETUP = (
    (ROS_TUTORIALS, "rospy_tutorials/005_add_two_ints/add_two_ints_server", (), None),
    (None, "fibonacci_server.py", (), COMMON_TUTORIALS),
    (None, "hello_world_publisher.py", (), None),
    (None, "static_transform_publisher.py", ("0", "0", "0", "0", "0", "0", "/world", "/turtle1", "100"), None),
)


def port_free(port: int) -> bool:
    with socket.socket() as s:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)  # as the server binds: TIME-WAIT is no owner
        try:
            s.bind(("127.0.0.1", port))
        except OSError:
            return False
    return True


def results_of(report: dict) -> list[tuple[str, str, str]]:
    """(file, test's full name, status, first line of its failure) from vitest's JSON report."""
    rows = []
    for file_result in report.get("testResults", []):
        name = Path(file_result.get("name", "?")).name
        assertions = file_result.get("assertionResults", [])
        if not assertions:  # a file that failed before its tests ran
            message = (file_result.get("message") or "failed to run").strip().splitlines()
            rows.append((f"{name}: (the file)", "failed", message[0] if message else ""))
        for a in assertions:
            failure = "".join(a.get("failureMessages") or []).strip().splitlines()
            rows.append(
                (
                    f"{name}: {a.get('fullName', a.get('title', '?'))}",
                    a.get("status", "?"),
                    failure[0] if failure else "",
                )
            )
    return rows


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("checkout", type=Path, help="a roslibjs checkout with its node_modules (npm ci)")
    parser.add_argument(
        "--corpus", type=Path, nargs="+", required=True, help="the corpus folders (bench/ros_corpus.py)"
    )
    parser.add_argument("--lab", type=Path, default=ROOT, help="the lab's checkout (its .venv/bin/hri-lab)")
    parser.add_argument("--verbose", action="store_true", help="print the setup programs' and vitest's output")
    parser.add_argument("--tests", nargs="+", default=list(TESTS), help=f"vitest's filters (default {' '.join(TESTS)})")
    parser.add_argument(
        "--own-network",
        action="store_true",
        help="run in a network namespace of its own (root: unshare --net), so its port 9090 is nobody else's",
    )
    args = parser.parse_args(argv)
    if args.own_network:
        rest = [a for a in (sys.argv[1:] if argv is None else argv) if a != "--own-network"]
        command = [sys.executable, "-m", "bench.roslibjs_suite", *rest]
        # a new namespace has only a loopback interface, down: bring it up, then run this again in it
        return subprocess.call(
            ["unshare", "--net", "--", "sh", "-c", 'ip link set lo up && exec "$@"', "sh", *command], cwd=ROOT
        )
    stop_on_sigterm()
    checkout = args.checkout.resolve()
    vitest = checkout / "node_modules" / ".bin" / "vitest"
    if not (checkout / "test" / "examples").is_dir() or not vitest.is_file():
        print(
            f"{checkout}: no test/examples or node_modules/.bin/vitest (a roslibjs checkout after `npm ci`?)",
            file=sys.stderr,
        )
        return 1
    if not (checkout / "dist").is_dir():
        built = subprocess.run(["npx", "vite", "build"], cwd=checkout, capture_output=True, text=True, timeout=600)
        if built.returncode != 0:
            print(f"{checkout}: `npx vite build` failed:\n{(built.stdout + built.stderr)[-2000:]}", file=sys.stderr)
            return 1
    if not port_free(PORT):
        print(f"port {PORT} is taken (another lab or rosbridge?): the tests need it", file=sys.stderr)
        return 1
    lab = Lab(args.lab)
    checkouts = find_checkouts(args.corpus)
    programs: list[tuple[Path, Sequence[str], Path | None]] = []
    for checkout_key, path, extra, workspace_key in SETUP:
        folder = corpus_folder(checkouts, checkout_key) if checkout_key else NODES
        workspace = corpus_folder(checkouts, workspace_key) if workspace_key else None
        if folder is None or (workspace_key and workspace is None):
            return 1
        programs.append((folder / path, extra, workspace))
    with tempfile.TemporaryDirectory(prefix="roslibjs-suite-") as tmp:
        work = Path(tmp)
        with serving(lab, work, PORT) as url:
            nodes = [
                Process([str(lab.command), "run", "--url", url, *workspace_args(w), str(p), *extra], cwd=work)
                for p, extra, w in programs
            ]
            run: subprocess.CompletedProcess[str] | None = None
            try:
                wait_for_setup(nodes)
                report_file = work / "vitest.json"
                run = subprocess.run(
                    [
                        str(vitest),
                        "run",
                        "--reporter=json",
                        "--reporter=verbose",
                        f"--outputFile.json={report_file}",
                        *args.tests,
                    ],
                    cwd=checkout,
                    capture_output=True,
                    text=True,
                    timeout=SUITE_TIMEOUT_S,
                    stdin=subprocess.DEVNULL,
                )
            finally:
                for node in nodes:
                    node.stop()
                if args.verbose and run is not None:
                    print((run.stdout + run.stderr)[-4000:])
                if args.verbose:
                    for (path, _, _), node in zip(programs, nodes, strict=True):
                        print(f"--- {path.name}")
                        for line in node.lines[-30:]:
                            print(f"| {line}")
            if not report_file.is_file():
                said = (run.stdout + run.stderr)[-3000:] if run is not None else ""
                print("vitest wrote no report:\n" + said, file=sys.stderr)
                return 1
            rows = results_of(json.loads(report_file.read_text()))
    for name, status, failure in rows:
        print(f"{'PASS' if status == 'passed' else status.upper()} {name}" + (f": {failure}" if failure else ""))
    passed = sum(status == "passed" for _, status, _ in rows)
    print(f"roslibjs ({', '.join(args.tests)}): {passed} passed, {len(rows) - passed} failed")
    return 0


def corpus_folder(checkouts: dict[tuple[str, str], Path], key: tuple[str, str]) -> Path | None:
    repo, commit = key
    folder = next((f for (r, c), f in checkouts.items() if r == repo and commit.startswith(c)), None)
    if folder is None:
        print(f"no {repo.replace('/', '+')}@{commit[:12]} folder in the corpus", file=sys.stderr)
    return folder


def workspace_args(workspace: Path | None) -> list[str]:
    return ["--workspace", str(workspace)] if workspace else []


def wait_for_setup(nodes: Sequence[Process]) -> None:
    """Until /listener is among rosapi's topics (setup_examples.bash waits for it too): a bounded
    wait; a setup node that ended is reported, and the tests run all the same."""
    import roslibpy

    ros = roslibpy.Ros("127.0.0.1", PORT)
    ros.run(timeout=SETUP_S)  # the lab is up: serving() waited for it
    try:
        deadline = time.monotonic() + SETUP_S
        while time.monotonic() < deadline:
            if "/listener" in ros.get_topics():
                break
            time.sleep(0.5)
        else:
            print(f"setup: /listener not published within {SETUP_S:g} s", file=sys.stderr)
    finally:
        ros.close()
    for node in nodes:
        if node.status() is not None:
            tail = "\n".join(node.lines[-5:])
            print(
                f"setup: {' '.join(map(str, node.proc.args[4:]))} ended with status {node.status()}:\n{tail}",
                file=sys.stderr,
            )


if __name__ == "__main__":
    sys.exit(main())
