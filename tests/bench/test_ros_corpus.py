"""bench/ros_corpus.py without the corpus (CI fetches nothing): the committed manifest reads, and the
bench finds the checkouts and judges what programs print as docs/ros-programs.md says."""

import re

import pytest

from bench.ros_corpus import (
    MANIFEST,
    ManifestError,
    Observed,
    Start,
    checkout_of,
    find_checkouts,
    first_error_line,
    judge,
    load_manifest,
    parse_manifest,
    summary,
)

COMMIT = "cbb174232b322eb3231d54af05765558c093ceca"
TRACEBACK = [
    "Traceback (most recent call last):",
    '  File "talker.py", line 41, in main',
    "    with rclpy.init(args=args):",
    "TypeError: 'NoneType' object does not support the context manager protocol",
]


def entry(**fields) -> str:
    base = {"repo": '"ros2/demos"', "commit": f'"{COMMIT}"', "path": '"talker.py"', "client": '"rclpy"'}
    base.update(fields)
    return "[[program]]\n" + "\n".join(f"{k} = {v}" for k, v in base.items()) + "\n"


def one(**fields):
    (program,) = parse_manifest(entry(**fields))
    return program


def test_the_committed_manifest_is_a_corpus_of_rclpy_and_rospy_programs_each_with_a_verdict():
    programs = load_manifest()
    assert MANIFEST.name == "ros_corpus.toml"
    assert len(programs) >= 30
    assert {p.client for p in programs} == {"rclpy", "rospy"}
    assert len({(p.repo, p.commit) for p in programs}) >= 5
    for p in programs:
        assert p.expect or p.checks or p.topics or p.exit is not None, p.name
        assert re.fullmatch(r"[0-9a-f]{40}", p.commit), p.name
        assert p.path not in [partner.path for partner in p.partners], p.name


def test_a_manifest_entry_reads_into_its_program():
    p = one(
        partners='["listener.py"]',
        args='["2", "3"]',
        expect='[{ in = "partner", line = "I heard: \\\\[Hello" }, { line = "Publishing" }]',
        checks='[{ hri_lab = ["service", "call", "/add_two_ints", "{a: 2, b: 3}"], line = "5" }]',
        exit="0",
        timeout="12.5",
    )
    assert p.partners == (Start("listener.py"),)
    assert p.args == ("2", "3")
    assert p.exit == 0
    assert p.timeout == 12.5
    assert [(e.where, e.pattern.pattern) for e in p.expect] == [
        ("partner", r"I heard: \[Hello"),
        ("program", "Publishing"),
    ]
    assert p.checks[0].args == ("service", "call", "/add_two_ints", "{a: 2, b: 3}")
    assert p.name == f"ros2/demos@{COMMIT[:12]}:talker.py"


def test_a_program_started_by_its_package_runs_as_its_docs_start_it_and_its_partners_too(tmp_path):
    run = one(
        path='"pkg/pkg/server.py"',
        package='"pkg"',
        executable='"server"',
        args='["--ros-args", "-p", "x:=1"]',
        partners='["client.py", { path = "pkg/pkg/client.py", package = "pkg", executable = "client", args = ["5"] }]',
        exit="0",
    )
    assert run.start.command(tmp_path) == ["pkg", "server", "--ros-args", "-p", "x:=1"]
    assert [p.command(tmp_path) for p in run.partners] == [[str(tmp_path / "client.py")], ["pkg", "client", "5"]]
    assert [str(p) for p in run.partners] == ["client.py", "pkg client"]  # how a failing partner is named
    launched = one(path='"pkg/launch/demo.launch.py"', package='"pkg"', launch="true", exit="0")
    assert launched.start.launch and launched.start.command(tmp_path) == ["pkg", "demo.launch.py"]
    by_file = one(path='"talker.py"', args='["2"]', exit="0")
    assert by_file.start.command(tmp_path) == [str(tmp_path / "talker.py"), "2"]


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        ({"exit": "0", "colour": '"red"'}, r"program 1 \(talker.py\): unknown field colour"),
        ({"exit": "0", "commit": '"cbb1742"'}, "full 40-digit commit"),
        ({"exit": "0", "client": '"roscpp"'}, "`client` must be one of rclpy, rospy"),
        ({"exit": "0", "repo": '"demos"'}, "owner/name"),
        ({"expect": '[{ line = "(" }]'}, "expect 1: `line` is no regular expression"),
        ({"expect": '[{ in = "partner", line = "x" }]'}, "needs `partners`"),
        ({"exit": "0", "executable": '"talker"'}, "`executable` needs its `package`"),
        ({"exit": "0", "package": '"demo_nodes_py"'}, "`package` needs the `executable`"),
        ({"exit": "0", "package": '"p"', "executable": '"x"', "launch": "true"}, "a launch file has no `executable`"),
        ({"exit": "0", "partners": '[{ package = "p", executable = "x" }]'}, r"partner 1: a path, or a table"),
        ({"topics": '[{ name = "/tf", type = "tf2_msgs/TFMessage", colour = "red" }]'}, "name and type"),
        ({"exit": "0", "partners": '[{ path = "l.py", executable = "x" }]'}, r"partner 1: `executable` needs"),
        ({"expect": '[{ in = "server", line = "x" }]'}, "`in` must be program or partner"),
        ({"checks": '[{ hri_lab = "service call", line = "x" }]'}, "`hri_lab` must be a list of strings"),
        ({"exit": "true"}, "`exit` must be an integer"),
        ({"exit": "0", "timeout": "0"}, "`timeout` must be seconds"),
        ({"exit": "0", "interrupt": '"("'}, "`interrupt` is no regular expression"),
        ({"expect": '[{ line = "x" }]', "interrupt": '"Hit ctrl-C"'}, "`interrupt` needs the `exit` status"),
        ({}, "nothing to judge it by"),
    ],
)
def test_a_wrong_manifest_entry_is_refused_naming_the_entry_and_the_field(fields, message):
    with pytest.raises(ManifestError, match=message):
        parse_manifest(entry(**fields))


def test_a_program_listed_twice_and_a_manifest_that_is_no_toml_are_refused():
    with pytest.raises(ManifestError, match="listed twice"):
        parse_manifest(entry(exit="0") + entry(exit="1"))
    with pytest.raises(ManifestError, match="not TOML"):
        parse_manifest("[[program]\n")


def test_checkouts_are_found_by_their_folder_names_given_or_inside_a_given_folder(tmp_path):
    demos = tmp_path / f"ros2+demos@{COMMIT[:12]}"
    other = tmp_path / "elsewhere" / "ros+ros_tutorials@db6328879831"
    for folder in (demos, other, tmp_path / "notes"):
        folder.mkdir(parents=True)
    (tmp_path / "ros2+examples@4a4082a8db04").write_text("a file, not a checkout")
    found = find_checkouts([tmp_path, other])
    assert found == {("ros2/demos", COMMIT[:12]): demos, ("ros/ros_tutorials", "db6328879831"): other}
    program = one(exit="0")
    assert checkout_of(program, found) == demos
    assert checkout_of(one(exit="0", commit='"' + "a" * 40 + '"'), found) is None  # another commit


def test_the_error_line_is_a_tracebacks_exception_else_the_first_logged_error():
    assert first_error_line(["starting", *TRACEBACK, "done"]) == TRACEBACK[-1]
    logged = ["[INFO] [1.0] [talker]: Publishing", "[ERROR] [1.1] [client]: Exception while calling service"]
    assert first_error_line(logged) == logged[1]
    assert first_error_line(["rospy.ROSSerializationException: header field"]).startswith("rospy.ROS")
    assert first_error_line(["I heard: [Hello World: 1]", "no mistakes here"]) is None
    launched = ["[param_talker] [INFO] [1.0]: /global_example is global value"] + [
        f"[param_talker] {t}" for t in TRACEBACK
    ]
    assert first_error_line(launched) == TRACEBACK[-1]  # hri-lab launch names each line's node
    assert first_error_line(["[talker] [ERROR] [1.0]: no"]) == "[ERROR] [1.0]: no"


def test_a_program_passes_once_every_line_and_check_is_seen_and_waits_until_then():
    p = one(partners='["listener.py"]', expect='[{ in = "partner", line = "I heard: \\\\[Hello World: \\\\d+\\\\]" }]')
    seen = Observed(program=['Publishing: "Hello World: 0"'], partners=[[]], partner_exits=[None])
    assert judge(p, seen, timed_out=False) is None
    seen.partners = [["[INFO] [listener]: I heard: [Hello World: 0]"]]
    verdict = judge(p, seen, timed_out=False)
    assert verdict is not None
    assert verdict.passed


def test_a_line_never_seen_fails_at_the_bound_naming_it_and_what_the_program_said():
    p = one(partners='["listener.py"]', expect='[{ in = "partner", line = "I heard" }]', timeout="30")
    seen = Observed(program=["[ERROR] [talker]: cannot publish"], partners=[[]], partner_exits=[None])
    verdict = judge(p, seen, timed_out=True)
    assert verdict is not None
    assert not verdict.passed
    assert verdict.reason == "waited 30 s for a line /I heard/ from the partner: [ERROR] [talker]: cannot publish"


def test_a_program_that_crashes_fails_at_once_with_its_exception_line():
    p = one(expect='[{ line = "Publishing" }]')
    verdict = judge(p, Observed(program=TRACEBACK, program_exit=1), timed_out=False)
    assert verdict is not None
    assert not verdict.passed
    assert verdict.reason == f"ended (status 1) before a line /Publishing/ from the program: {TRACEBACK[-1]}"


def test_a_program_expected_to_end_passes_on_its_status_and_fails_on_another():
    p = one(expect='[{ line = "Result of add_two_ints: 5" }]', exit="0")
    done = Observed(program=["Result of add_two_ints: 5"], program_exit=0)
    assert judge(p, done, timed_out=False).passed  # type: ignore[union-attr]
    running = Observed(program=["Result of add_two_ints: 5"])
    assert judge(p, running, timed_out=False) is None  # seen, not ended yet
    assert judge(p, running, timed_out=True).reason == "did not end within 40 s"  # type: ignore[union-attr]
    crashed = judge(p, Observed(program=TRACEBACK, program_exit=1), timed_out=False)
    assert crashed is not None
    assert crashed.reason == f"exited with status 1: {TRACEBACK[-1]}"
    quiet = judge(p, Observed(program=["Goal failed to cancel"], program_exit=0), timed_out=False)
    assert quiet is not None
    assert quiet.reason == "ended (status 0) before a line /Result of add_two_ints: 5/ from the program"


def test_a_partner_that_crashes_fails_the_program_naming_the_partner():
    p = one(partners='["listener.py"]', expect='[{ in = "partner", line = "I heard" }]')
    seen = Observed(program=["Publishing"], partners=[TRACEBACK], partner_exits=[1])
    verdict = judge(p, seen, timed_out=False, partner_names=["listener.py"])
    assert verdict is not None
    assert verdict.reason == f"partner listener.py exited with status 1: {TRACEBACK[-1]}"


def test_checks_pass_in_order_and_a_failing_one_is_reported_with_its_last_output():
    p = one(checks='[{ hri_lab = ["param", "get", "/node", "param2"], line = "4\\\\.0" }]')
    seen = Observed(last_check_output="error: parameter 'param2' not set\n")
    assert judge(p, seen, timed_out=False) is None
    verdict = judge(p, seen, timed_out=True)
    assert verdict is not None
    assert (
        verdict.reason
        == "waited 40 s for `hri-lab param get /node param2` printing /4\\.0/ (last: error: parameter 'param2' not set)"
    )
    seen.checks_matched = 1
    assert judge(p, seen, timed_out=False).passed  # type: ignore[union-attr]


def test_the_summary_counts_each_client_and_the_pass_rate():
    from bench.ros_corpus import Verdict

    r = one(exit="0")
    s = one(exit="0", client='"rospy"', path='"talker.py"', repo='"ros/ros_tutorials"')
    text = summary([(r, Verdict(True, "")), (r, Verdict(False, "x")), (s, Verdict(True, ""))])
    assert text.splitlines() == ["rclpy: 1 of 2 pass", "rospy: 1 of 1 pass", "pass rate: 2 of 3 (67 %)"]


def test_the_report_is_a_markdown_table_failures_first_with_the_command_and_the_load():
    from bench.ros_corpus import Verdict, report

    ok = one(exit="0", why='"a timer publishing"')
    bad = one(exit="0", path='"listener.py"', why='"a subscription"')
    text = report(
        [(ok, Verdict(True, "")), (bad, Verdict(False, "exited with status 1: x | y"))],
        "main 7f4017d",
        "python -m bench.ros_corpus /c",
        (12.5, 11.0, 9.25),
    )
    lines = text.splitlines()
    assert lines[0] == "# Public ROS programs, unchanged: the results"
    assert "`python -m bench.ros_corpus /c`" in lines[5]
    assert "load average 12.5 11.0 9.2" in lines[6]
    assert "- pass rate: 1 of 2 (50 %)" in lines
    rows = [line for line in lines if line.startswith("| ros2/demos")]
    assert rows == [
        f"| ros2/demos@{COMMIT[:12]} | `listener.py` | a subscription | **fail**: exited with status 1: x \\| y |",
        f"| ros2/demos@{COMMIT[:12]} | `talker.py` | a timer publishing | pass |",
    ]


def test_a_topic_with_a_line_is_heard_only_from_a_message_that_matches_it():
    """A program's frame on /tf: the lab's own /tf messages (without it) do not count."""
    (heard,) = one(
        topics='[{ name = "/tf", type = "tf2_msgs/TFMessage", line = "\\"child_frame_id\\": \\"carrot1\\"" }]'
    ).topics
    lab = {"transforms": [{"header": {"frame_id": "world"}, "child_frame_id": "panda_link0"}]}
    assert not heard.matches(lab)
    assert heard.matches(
        {"transforms": [*lab["transforms"], {"header": {"frame_id": "turtle1"}, "child_frame_id": "carrot1"}]}
    )
    (any_message,) = one(topics='[{ name = "/chatter", type = "std_msgs/String" }]').topics
    assert any_message.matches({"data": ""})
