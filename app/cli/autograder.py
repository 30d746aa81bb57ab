"""`hri-lab autograder -o autograder.zip`: the bundle Gradescope takes (docs/course-scale.md).

Gradescope's autograder (https://gradescope-autograders.readthedocs.io/en/latest/specs/) unzips
the bundle into /autograder/source, runs its `setup.sh` once as root to build the image, then,
for every submission, its `run_autograder` with the student's files in /autograder/submission/;
that writes /autograder/results/results.json. Ours:
- setup.sh installs bubblewrap (apt) and this very lab (its source is in the bundle, uv
  installs it with its pinned dependencies) into a virtual environment /autograder/hri-lab;
- run_autograder runs `python -m app.grading.gradescope` (app/grading/gradescope.py): the battery
  of `hri-lab grade` on the submission's controller file, with the bundle's seed, each item a test;
  with --services also the services exercises (`hri-lab grade-services`) of the submission's
  services_node.py, run against a lab started in the container with `serve --exercises`.
  Where bubblewrap cannot create its namespaces (Gradescope's container may forbid them) the file
  runs with the child-process limits alone, and the output says so: the container is the sandbox.
$HRI_LAB_GRADESCOPE_ROOT (default /autograder) moves the whole layout (the tests use it);
$HRI_LAB_PYTHON names the interpreter run_autograder uses.
"""

from __future__ import annotations

import argparse
import json
import sys
import zipfile

from app.cli.handout import lab_files
from app.grading.report import PUBLIC_SEED, seed_note

CONFIG = "hri-lab-autograder.json"  # in the bundle: the seed and how results are shown
SOURCE = "hri-lab"  # the lab's source in the bundle (uv installs it)
UV = "uv==0.13.9"  # the installer setup.sh and the Makefile run (pip installs it first, into the lab's venv)

PYTHON_NEEDED = (3, 11)  # pyproject.toml's requires-python
BASE_IMAGE = "Ubuntu 24.04"  # Gradescope's base image to pick: its python3 is 3.12 (22.04's, the default, is 3.10)

SETUP_SH = """#!/usr/bin/env bash
# Gradescope runs this once, as root, when it builds the image. Pick the {base_image} base image
# (python3 3.12); on Ubuntu 22.04 (python3 3.10) Ubuntu's python3.11 is installed. hri-lab {version}
# needs Python >= {needed}: this script finds or installs one, checks it, and stops with a message
# when there is none. Then bubblewrap (the sandbox) and this lab with its pinned dependencies{nodes}
# in a virtual environment of its own, and its compiled kernels.
set -euo pipefail
ROOT="${{HRI_LAB_GRADESCOPE_ROOT:-/autograder}}"
version_ok() {{ "$1" -c 'import sys; sys.exit(sys.version_info < ({needed_tuple}))' 2>/dev/null; }}
venv_ok() {{ "$1" -c 'import ensurepip, venv' 2>/dev/null; }}
apt_install() {{ apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" >/dev/null; }}
PYTHON=""
for candidate in python3 python3.13 python3.12 python3.11; do
  if command -v "$candidate" >/dev/null && version_ok "$candidate"; then PYTHON="$(command -v "$candidate")"; break; fi
done
if [ -z "$PYTHON" ]; then
  apt_install python3.11 python3.11-venv || true
  if command -v python3.11 >/dev/null && version_ok python3.11; then PYTHON="$(command -v python3.11)"; fi
fi
if [ -z "$PYTHON" ]; then
  echo "setup.sh: hri-lab needs Python >= {needed}; this image has $(python3 --version 2>&1) and no python3.11 package:" \
    "pick Gradescope's {base_image} base image" >&2
  exit 1
fi
venv_ok "$PYTHON" || apt_install "$(basename "$PYTHON")-venv"
command -v bwrap >/dev/null || apt_install bubblewrap
echo "setup.sh: $("$PYTHON" --version) at $PYTHON"
"$PYTHON" -m venv "$ROOT/hri-lab"
# uv installs the lab's pinned dependencies several times faster than pip; byte-compiled now, as pip
# does, since every submission's container starts from this image and would otherwise compile them
"$ROOT/hri-lab/bin/pip" install --quiet {uv}
"$ROOT/hri-lab/bin/uv" pip install --quiet --compile-bytecode --python "$ROOT/hri-lab/bin/python" \
  --editable "$ROOT/source/{source}{extras}"
# the simulation's compiled kernels, cached now rather than by every submission's grade
"$ROOT/hri-lab/bin/python" -c "from sim.warm_up import warm_up; warm_up()"
"""

RUN_AUTOGRADER = """#!/usr/bin/env bash
# Gradescope runs this for every submission: grades /autograder/submission/ and writes
# /autograder/results/results.json (python -m app.grading.gradescope; docs/course-scale.md).
set -euo pipefail
ROOT="${{HRI_LAB_GRADESCOPE_ROOT:-/autograder}}"
PYTHON="${{HRI_LAB_PYTHON:-$ROOT/hri-lab/bin/python}}"
cd "$ROOT"
exec "$PYTHON" -m app.grading.gradescope "$ROOT/source/{config}"
"""


def version() -> str:
    from importlib.metadata import version as installed

    return installed("hri-lab")


def build(args: argparse.Namespace) -> int:
    """Write the bundle; 2 when the lab's source is not where its packages are (a wheel install)."""
    if args.seed == PUBLIC_SEED and not args.public_seed:
        print(
            f"hri-lab autograder: seed {PUBLIC_SEED} is the public default: every student can run this grade at "
            "home and learn its numbers. Give the course's private --seed N (or $HRI_LAB_GRADE_SEED), or "
            "--public-seed for a trial run",
            file=sys.stderr,
        )
        return 2
    files = lab_files()
    if not files[0][0].is_file():
        print("hri-lab autograder: the lab's source (pyproject.toml) is not beside its packages", file=sys.stderr)
        return 2
    config = {
        "seed": args.seed,
        "hide_until_due": args.hide_until_due,
        "services": args.services,
        "reference": args.reference,
        "version": version(),
    }
    with zipfile.ZipFile(args.output, "w", zipfile.ZIP_DEFLATED) as bundle:
        for name, text in (
            (
                "setup.sh",
                SETUP_SH.format(
                    version=config["version"],
                    source=SOURCE,
                    base_image=BASE_IMAGE,
                    needed=".".join(map(str, PYTHON_NEEDED)),
                    needed_tuple=", ".join(map(str, PYTHON_NEEDED)),
                    nodes=" (and roslibpy, for students' roslibpy nodes)" if args.services else "",
                    extras="[nodes]" if args.services else "",
                    uv=UV,
                ),
            ),
            ("run_autograder", RUN_AUTOGRADER.format(config=CONFIG)),
        ):
            info = zipfile.ZipInfo(name)
            info.external_attr = 0o100755 << 16  # executable, as Gradescope runs them
            info.compress_type = zipfile.ZIP_DEFLATED
            bundle.writestr(info, text)
        bundle.writestr(CONFIG, json.dumps(config, indent=2) + "\n")
        for path, name in files:
            bundle.write(path, f"{SOURCE}/{name}")
    print(f"{args.output}: setup.sh, run_autograder, hri-lab {config['version']}, {seed_note(args.seed)}")
    return 0


def run(args: argparse.Namespace) -> int:
    return build(args)
