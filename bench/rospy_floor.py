"""What the machine alone costs a rospy subscriber of F_ext (issue 31's figure has no lab-free
reference otherwise): a 1 kHz stream over plain TCP on loopback, sent by a process paced as the
lab's loop is (a message per 1 ms tick; late ticks sent back to back), into rospy's own receive
rule with bench/fext_callback.py's callback. No lab, no rosbridge, no JSON.

rospy's rule, as ros_comm's source has it (impl/tcpros_base.py `receive_once` and `receive_loop`,
msg.py `deserialize_messages`): one thread per connection reads what the socket holds (up to
buff_size, 65536 bytes), keeps the newest queue_size of the complete messages in it, and runs the
callback on each, on that same thread, before it reads again. The messages are TCPROS frames (a
4-byte length, then the message) of a WrenchStamped's size.

    .venv/bin/python -m bench.rospy_floor [--seconds 5] [--queue-size 1]

prints one JSON line: published, handled, slow (callbacks over 1 ms), dropped (%).
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import socket
import struct
import time

from bench.fext_callback import PERIOD_S, Tally

BUFF_SIZE = 65536  # bytes, rospy.Subscriber's buff_size default
FRAME_ID = b"panda_link8"
_BODY = struct.Struct(f"<4I{len(FRAME_ID)}s6d")  # seq, stamp (secs, nsecs), frame_id (length, text), wrench


def frame(tick: int) -> bytes:
    """The TCPROS frame of the tick's WrenchStamped: its length, then the message."""
    stamp_ns = tick * round(PERIOD_S * 1e9)
    body = _BODY.pack(tick, stamp_ns // 10**9, stamp_ns % 10**9, len(FRAME_ID), FRAME_ID, 0, 0, 5.0, 0, 0, 0)
    return struct.pack("<I", len(body)) + body


def send(port: int, seconds: float, max_behind_s: float) -> None:
    """The publisher: one WrenchStamped per tick of PERIOD_S, stamped with its tick's time; further
    than max_behind_s behind, it drops the missed ticks, as the lab's loop does."""
    listener = socket.create_server(("127.0.0.1", port))
    peer, _ = listener.accept()
    peer.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)  # rospy's tcp_nodelay for a 1 kHz topic
    next_tick, tick = time.perf_counter(), 0
    while tick * PERIOD_S < seconds:
        peer.sendall(frame(tick))
        tick += 1
        next_tick += PERIOD_S
        now = time.perf_counter()
        if now - next_tick > max_behind_s:
            next_tick = now
        elif next_tick > now:
            time.sleep(next_tick - now)
    peer.close()
    listener.close()


def receive_once(buffered: bytes, queue_size: int) -> tuple[list[bytes], bytes]:
    """rospy's rule on what was read: the newest `queue_size` complete messages (the older ones are
    dropped), and the bytes of an incomplete one, kept for the next read."""
    frames, at = [], 0
    while len(buffered) - at >= 4:
        (size,) = struct.unpack_from("<I", buffered, at)
        if len(buffered) - at - 4 < size:
            break
        frames.append(buffered[at + 4 : at + 4 + size])
        at += 4 + size
    return frames[-queue_size:], buffered[at:]


def receive(port: int, queue_size: int) -> Tally:
    """The subscriber: read what the socket holds, rospy's rule, the callback on each message kept."""
    tally = Tally()
    sock = socket.create_connection(("127.0.0.1", port), timeout=30)
    sock.settimeout(None)
    buffered = b""
    while True:
        data = sock.recv(BUFF_SIZE)
        if not data:
            return tally
        kept, buffered = receive_once(buffered + data, queue_size)
        for frame in kept:
            _, secs, nsecs = struct.unpack_from("<3I", frame)
            tally.handle(secs * 10**9 + nsecs)


def measure(seconds: float, queue_size: int = 1) -> dict:
    probe = socket.socket()
    probe.bind(("127.0.0.1", 0))
    port = probe.getsockname()[1]
    probe.close()
    from app.runtime.loop import SimulationLoop  # here, not at the top: the spawned sender imports no simulation

    sender = multiprocessing.get_context("spawn").Process(
        target=send, args=(port, seconds, SimulationLoop.max_behind), daemon=True
    )
    sender.start()
    deadline = time.monotonic() + 60
    while True:  # the sender is listening
        try:
            tally = receive(port, queue_size)
            break
        except ConnectionRefusedError:
            if time.monotonic() > deadline:
                raise
            time.sleep(0.05)
    sender.join(timeout=60)
    if sender.exitcode != 0:
        raise RuntimeError(f"the sender failed (exit code {sender.exitcode})")
    figures = tally.figures()
    figures["dropped"] = round(100 * (1 - figures["handled"] / figures["published"]), 1) if figures["published"] else 0
    return figures


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--queue-size", type=int, default=1)
    args = parser.parse_args(argv)
    print(json.dumps(measure(args.seconds, args.queue_size)), flush=True)


if __name__ == "__main__":
    main()
