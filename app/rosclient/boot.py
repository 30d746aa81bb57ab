"""A student's program as `hri-lab run` starts it: `python -m app.rosclient.boot FILE [ARGS...]`.

Only this process gets the ROS client libraries (app/rosclient/site) on sys.path, the interface
finder and cv2's window hook (app/rosclient/windows.py) on sys.meta_path; then FILE runs as `__main__` with sys.argv = [FILE, ARGS...] (its
`--ros-args` included, as ros2 run passes them), its folder first on sys.path like `python FILE`,
then its own Python package's and its workspace's packages (app/rosclient/packages.py).
"""

from __future__ import annotations

import os
import runpy
import sys
from pathlib import Path

SITE = Path(__file__).parent / "site"


def main() -> None:
    if len(sys.argv) < 2:
        print("usage: python -m app.rosclient.boot FILE.py [ARGS...]", file=sys.stderr)
        raise SystemExit(2)
    program = Path(sys.argv[1])
    from app.interfaces.parser import DefinitionError
    from app.rosclient import interfaces, packages, process, windows

    windows.install()  # cv2.imshow / waitKey show on the lab's dashboard (app/rosclient/windows.py)
    workspace = os.environ.get("HRI_LAB_WORKSPACE") or None
    found = interfaces.install(interfaces.workspace_roots(program, workspace))
    found.named = packages.find(packages.workspace_of(program, workspace))  # by their package.xml names
    own = [str(p) for p in packages.python_paths(program, found.named)]  # as installed packages import
    sys.path[0:0] = [str(program.resolve().parent), *own, str(SITE)]
    sys.argv = [str(program), *sys.argv[2:]]
    try:
        runpy.run_path(str(program), run_name="__main__")
    except (ConnectionError, DefinitionError) as exc:  # the lab cannot be reached, as rospy says it of a
        print(f"[FATAL] {exc}", file=sys.stderr)  # master; a .msg/.srv/.action that cannot be read: its file and line
        raise SystemExit(1) from None
    finally:
        process.close()


if __name__ == "__main__":
    main()
