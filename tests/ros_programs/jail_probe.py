"""A wall follower that looks around instead of driving: it tries the host's files, the lab's
checkout, writing outside /tmp and a big /tmp file, and prints what each attempt met."""

import os

import app  # the lab's package, which `hri-lab run` imports


def attempt(what, action):
    try:
        action()
        print(f"{what}: allowed", flush=True)
    except OSError as exc:
        print(f"{what}: denied ({type(exc).__name__})", flush=True)


def write(path, size=1):
    with open(path, "wb") as f:
        f.write(b"x" * size)


here = os.path.dirname(os.path.abspath(__file__))
attempt("host file", lambda: open("/etc/hostname").read())  # noqa: SIM115 - the file stays open beyond this block (closed by its owner, or held on purpose)
attempt("checkout's tests", lambda: os.listdir(os.path.join(os.path.dirname(os.path.dirname(app.__file__)), "tests")))
attempt("own folder write", lambda: write(os.path.join(here, "left_behind.txt")))
attempt("tmp 100 MB", lambda: write("/tmp/big", 100 << 20))
