"""A student's program as `hri-lab run` starts it: `python -m rosclient.boot FILE [ARGS...]`.

Only this process gets the ROS client libraries (rosclient/site) on sys.path, the interface
finder and cv2's window hook (rosclient/windows.py) on sys.meta_path; then FILE runs as `__main__` with sys.argv = [FILE, ARGS...] (its
`--ros-args` included, as ros2 run passes them), its folder first on sys.path like `python FILE`,
then its own Python package's and its workspace's packages (rosclient/packages.py).

`python -m rosclient.boot --entry MODULE:FUNCTION FILE [ARGS...]` is a package's console_scripts
entry point (rosclient/executables.py): FILE is the entry point's module file (its workspace's
interfaces are found from it), MODULE imports from the package's sources and FUNCTION's return is the
exit status, as the script colcon installs runs it. A FILE that defines main() and never calls it
(no `if __name__ == "__main__":` block) has main() called after it ran, as its entry point would
have it, and that is said on stderr.
"""

from __future__ import annotations

import importlib
import os
import runpy
import sys
from pathlib import Path

SITE = Path(__file__).parent / "site"


def main() -> None:
    entry = None
    if len(sys.argv) > 2 and sys.argv[1] == "--entry":
        entry = sys.argv[2]
        del sys.argv[1:3]
    if len(sys.argv) < 2:
        print("usage: python -m rosclient.boot [--entry MODULE:FUNCTION] FILE.py [ARGS...]", file=sys.stderr)
        raise SystemExit(2)
    program = Path(sys.argv[1])
    from interfaces.parser import DefinitionError
    from rosclient import executables, interfaces, packages, process, windows

    windows.install()  # cv2.imshow / waitKey show on the lab's dashboard (rosclient/windows.py)
    workspace = os.environ.get("HRI_LAB_WORKSPACE") or None
    found = interfaces.install(interfaces.workspace_roots(program, workspace))
    found.named = packages.find(packages.workspace_of(program, workspace))  # by their package.xml names
    # as installed packages import; not a workspace's copy of a client library the lab provides (actionlib's
    # sources beside its tests): that one runs over the lab
    ours = {name: folder for name, folder in found.named.items() if not (SITE / name).is_dir()}
    own = [str(p) for p in packages.python_paths(program, ours)]
    first = [] if entry else [str(program.resolve().parent)]  # an installed script's folder holds no module
    sys.path[0:0] = [*first, *own, str(SITE)]
    sys.argv = [str(program), *sys.argv[2:]]
    try:
        if entry:
            module, _, function = entry.partition(":")
            raise SystemExit(getattr(importlib.import_module(module), function)())
        names = runpy.run_path(str(program), run_name="__main__")
        why = executables.main_call(_source(program))
        if why == "call":
            print(
                f'hri-lab run: {program.name} defines main() and has no `if __name__ == "__main__":` block: '
                "calling main(), as `ros2 run` calls a package's entry point",
                file=sys.stderr,
                flush=True,
            )
            raise SystemExit(names["main"]())
        if why:
            print(
                f'hri-lab run: {program.name} defines main() and never calls it (no `if __name__ == "__main__":` '
                f"block); main() {why}, so it was not called: nothing ran",
                file=sys.stderr,
            )
            raise SystemExit(1)
    except (ConnectionError, DefinitionError) as exc:  # the lab cannot be reached, as rospy says it of a
        print(f"[FATAL] {exc}", file=sys.stderr)  # master; a .msg/.srv/.action that cannot be read: its file and line
        raise SystemExit(1) from None
    finally:
        process.close()


def _source(program: Path) -> str:
    try:
        return program.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return ""


if __name__ == "__main__":
    main()
