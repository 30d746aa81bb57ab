"""`hri-lab record | play | bag info`: like `ros2 bag record`, `ros2 bag play`, `ros2 bag info`."""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from app.cli import arguments
from app.cli import client as c


def record(args) -> int:
    """Record the live lab until Ctrl+C (or --duration), then download the file to -o."""
    output = Path(args.output or time.strftime("hri-lab_%Y%m%d_%H%M%S.mcap"))
    if output.suffix != ".mcap":
        output = output.with_suffix(".mcap")
    if output.exists():
        raise c.CliError(f"{output} exists: choose another name with -o")
    response = c._request(args, "POST", "/services/start_recording", json={"name": output.stem, "max_mb": args.max_mb})
    if response.status_code != 200:
        raise c.CliError(f"cannot start recording: {c._detail(response)}")
    print(
        f"[INFO] recording the lab at {args.url} (server file {response.json()['path']}); press Ctrl+C to stop",
        file=sys.stderr,
        flush=True,
    )
    try:
        end = time.monotonic() + args.duration if args.duration else None
        while end is None or time.monotonic() < end:
            time.sleep(0.2 if end is None else max(0.0, min(0.2, end - time.monotonic())))
    except KeyboardInterrupt:
        pass
    response = c._request(args, "POST", "/services/stop_recording", json={})
    if response.status_code not in (200, 400):
        raise c.CliError(f"cannot stop recording: {c._detail(response)}")
    body = response.json()
    print(f"[INFO] {body.get('message') or body.get('detail')}", file=sys.stderr)
    if "path" not in body:
        return 1
    try:
        with (
            c._client(args) as client,
            client.stream("GET", f"/recordings/{Path(body['path']).name}", timeout=60.0) as download,
        ):
            if download.status_code != 200:
                raise c.CliError(f"cannot download the recording: HTTP {download.status_code}")
            with open(output, "wb") as f:
                for block in download.iter_bytes():
                    f.write(block)
    except c.httpx.HTTPError as exc:
        raise c.CliError(f"cannot download the recording: {exc}") from None
    print(output)
    return 0 if body.get("success") else 1


def info(args) -> int:
    """What `ros2 bag info` prints, of any bag: the lab's MCAP, a rosbag2 (folder, .mcap), a rosbag1 .bag."""
    from sim.recording import reader

    from app.recording import bags

    try:
        bag = bags.open_bag(args.file).info()
    except reader.RecordingError as exc:
        raise c.CliError(str(exc)) from None
    print(json.dumps(bag.as_dict(), indent=2) if args.json else reader.format_info(bag))
    return 0


def convert(args) -> int:
    """Any bag to a ROS 1 .bag (rosbag1), as `rosbags-convert` does."""
    from sim.recording import reader

    from app.recording import bags

    output = Path(args.output)
    if output.suffix != ".bag":
        raise c.CliError(f"{output}: a ROS 1 bag's name ends in .bag")
    try:
        count = bags.to_rosbag1(args.file, output)
    except reader.RecordingError as exc:
        raise c.CliError(str(exc)) from None
    print(f"[INFO] {count} messages written", file=sys.stderr)
    print(output)
    return 0


def _bag_record(args) -> int:
    from app.cli import bag_ros

    return bag_ros.record(args)


def _bag_play(args) -> int:
    from app.cli import bag_ros

    return bag_ros.play(args)


def play(args) -> int:
    """The recording in the 3D view with a slider, and its topics over HTTP, until Ctrl+C."""
    import uvicorn

    from sim.mobile.playback import is_mobile
    from sim.recording import reader
    from sim.recording.playback import Playback

    from app.serving.launch import free_port
    from app.view.replay import ReplayView, replay_app

    view: ReplayView
    try:
        if is_mobile(args.file):  # a mobile world's recording: its own reader and scene
            from sim.mobile.playback import MobilePlayback

            from app.view.mobile_view import MobileReplayView

            view = MobileReplayView(
                MobilePlayback(args.file), port=args.view_port or free_port(), light=args.view == "light"
            )
        else:
            view = ReplayView(Playback(args.file), port=args.view_port or free_port(), light=args.view == "light")
    except reader.RecordingError as exc:
        raise c.CliError(str(exc)) from None
    view.start()
    port = args.port or free_port()
    if args.play:
        view.play()
    print(
        f"hri-lab play: {view.playback.path.name}, {view.playback.duration:.2f} s, {len(view.playback.times)} frames\n"
        f"  3D view   {view.url}\n"
        f"  topics    http://127.0.0.1:{port}/topics  (hri-lab topic echo NAME --url http://127.0.0.1:{port})\n"
        "Press Ctrl+C to stop.",
        flush=True,
    )
    try:
        uvicorn.run(replay_app(view), host="127.0.0.1", port=port, log_level="warning", access_log=False)
    finally:
        view.stop()
    return 0


def add_parsers(sub: argparse._SubParsersAction) -> None:
    url = arguments.url_parent()
    rec = sub.add_parser("record", parents=[url], help="record the live lab to MCAP (like ros2 bag record)")
    rec.add_argument(
        "-o", "--output", metavar="FILE.mcap", help="where to save it (default hri-lab_<date>_<time>.mcap)"
    )
    rec.add_argument("--duration", type=float, help="stop after this many seconds (default: Ctrl+C)")
    rec.add_argument("--max-mb", type=float, default=1024.0, help="size cap: the recording stops there (MiB)")
    rec.set_defaults(func=record)

    ply = sub.add_parser("play", help="replay a recording in the 3D view, its topics over HTTP (like ros2 bag play)")
    ply.add_argument("file", metavar="FILE.mcap")
    ply.add_argument("--port", type=int, default=0, help="port of the topics API (default: a free one)")
    ply.add_argument("--view-port", type=int, default=0, help="port of the 3D view (default: a free one)")
    ply.add_argument(
        "--view", choices=("full", "light"), default="full", help="full meshes or light (collision meshes)"
    )
    ply.add_argument("--play", action="store_true", help="start playing at once (default: paused at 0)")
    ply.set_defaults(func=play)

    bag = sub.add_parser("bag", help="recordings (like ros2 bag)")
    bag_sub = bag.add_subparsers(dest="action", required=True)
    inf = bag_sub.add_parser("info", help="duration, topics, types and counts of a bag (rosbag info, ros2 bag info)")
    inf.add_argument("file", metavar="BAG", help="an hri-lab .mcap, a rosbag2 (folder or .mcap) or a ROS 1 .bag")
    inf.add_argument("--json", action="store_true")
    inf.set_defaults(func=info)

    brec = bag_sub.add_parser(
        "record", parents=[url], help="record topics of the lab's graph to a rosbag2 (like rosbag record)"
    )
    brec.add_argument("topics", nargs="*", metavar="TOPIC", help="the topics to record")
    brec.add_argument("-a", "--all", action="store_true", help="every topic, new ones as they appear")
    brec.add_argument("-e", "--regex", metavar="REGEX", help="the topics matching this regular expression")
    brec.add_argument("-x", "--exclude", metavar="REGEX", help="not the topics matching this regular expression")
    brec.add_argument(
        "-O",
        "-o",
        "--output-name",
        dest="output_name",
        metavar="NAME",
        help="the bag's folder (default rosbag2_<date>-<time>): NAME/NAME.mcap and NAME/metadata.yaml",
    )
    brec.add_argument("--duration", type=float, help="stop after this many seconds (default: Ctrl+C)")
    brec.add_argument(
        "--max-mb", type=float, default=1024.0, help="size cap of the messages (MiB): recording stops there"
    )
    brec.set_defaults(func=_bag_record)

    bply = bag_sub.add_parser(
        "play", parents=[url], help="publish a bag's topics into the lab over rosbridge (like rosbag play)"
    )
    bply.add_argument("file", metavar="BAG", help="an hri-lab .mcap, a rosbag2 (folder or .mcap) or a ROS 1 .bag")
    bply.add_argument("-l", "--loop", action="store_true", help="play again from the start at the end")
    bply.add_argument("-r", "--rate", type=float, default=1.0, help="rate multiplier (2: twice as fast)")
    bply.add_argument("--topics", nargs="+", default=[], metavar="TOPIC", help="only these topics")
    bply.add_argument("-s", "--start", type=float, default=0.0, help="start this many seconds into the bag")
    bply.add_argument("--clock", action="store_true", help="publish the bag's time on /clock (rosgraph_msgs/Clock)")
    bply.set_defaults(func=_bag_play)

    bcv = bag_sub.add_parser("convert", help="convert a bag to a ROS 1 .bag (rosbag1)")
    bcv.add_argument("file", metavar="BAG", help="an hri-lab .mcap, a rosbag2 (folder or .mcap) or a ROS 1 .bag")
    bcv.add_argument("output", metavar="OUT.bag")
    bcv.set_defaults(func=convert)
