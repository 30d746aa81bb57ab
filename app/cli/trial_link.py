"""A graded program's one way out of its jail (app/grading/wall_trial.py): runs inside the jail's own
network namespace, which holds nothing but its loopback, and forwards each connection to
127.0.0.1:PORT there (where the program's `hri-lab run --url` connects, as to any lab) to the trial's
lab through the Unix socket bind-mounted into the jail. Nothing of the host's loopback is in the
namespace: no other port, no other trial, no Dask; `/proc/net` lists only this listener and the
program's own sockets.

`python -m app.cli.trial_link SOCKET PORT -- COMMAND...`: listens first, then starts COMMAND (the
program: its connection never races the listener) and ends with it, with its exit status.
Standard library only: it runs in the jail beside the student's code and trusts nothing of it (the
program can only break its own link).
"""

from __future__ import annotations

import asyncio
import os
import socket
import sys
import threading

CHUNK = 64 * 1024


async def _pump(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
    try:
        while data := await reader.read(CHUNK):
            writer.write(data)
            await writer.drain()
    except (ConnectionError, OSError):
        pass
    finally:
        writer.close()


def _linker(lab_socket: str):
    async def link(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        try:
            lab_reader, lab_writer = await asyncio.open_unix_connection(lab_socket)
        except OSError:
            writer.close()
            return
        await asyncio.gather(_pump(reader, lab_writer), _pump(lab_reader, writer))

    return link


def _exit_code(status: int) -> int:
    code = os.waitstatus_to_exitcode(status)
    return code if code >= 0 else 128 - code  # killed by signal N: 128 + N, as a shell says


def main(argv: list[str]) -> int:
    if len(argv) < 4 or argv[2] != "--":
        print("usage: python -m app.cli.trial_link SOCKET PORT -- COMMAND...", file=sys.stderr)
        return 2
    lab_socket, port, command = argv[0], int(argv[1]), argv[3:]
    listener = socket.create_server(("127.0.0.1", port), backlog=64)
    pid = os.fork()
    if pid == 0:  # the program: without the listener
        listener.close()
        try:
            os.execvp(command[0], command)
        finally:
            os._exit(127)
    loop = asyncio.new_event_loop()
    status: list[int] = []

    def wait() -> None:
        status.append(os.waitpid(pid, 0)[1])
        loop.call_soon_threadsafe(loop.stop)

    threading.Thread(target=wait, daemon=True).start()
    loop.run_until_complete(asyncio.start_server(_linker(lab_socket), sock=listener))
    loop.run_forever()
    return _exit_code(status[0])


if __name__ == "__main__":
    sys.stdout.flush()
    os._exit(main(sys.argv[1:]))
