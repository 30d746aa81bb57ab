"""bench/ros1_oracle.py's pure parts: what is masked, and a difference found unless it is known."""

from bench import ros1_oracle
from bench.ros1_oracle import KNOWN, Case, Seen, Step, differences, masked


def test_times_anonymous_names_and_addresses_are_masked_and_nothing_else():
    assert masked("[INFO] [1733491234.567890]: Returning [3 + 4 = 7]") == "[INFO] [T]: Returning [3 + 4 = 7]"
    assert masked("node /listener_21197_1796573200968") == "node /listener_N"
    assert masked("at http://127.0.0.1:11311/ now") == "at URI now"
    assert masked("3 + 4 = 7") == "3 + 4 = 7"
    assert masked("node /talker_2") == "node /talker_2"  # a name's own number stays


def test_a_difference_is_reported_unless_listed_with_its_reason(monkeypatch):
    case = Case("c", [Step("p.py")])
    same = Seen({"p.py": ["a"]}, {"node /p"}, {})
    assert differences(case, same, same) == []
    found = differences(case, same, Seen({"p.py": ["b"]}, {"node /p", "service /q"}, {}))
    assert len(found) == 2
    assert "p.py printed" in found[0]
    assert "'service /q' only under the lab" in found[1]
    failed = differences(case, same, Seen({"p.py": ["a"]}, {"node /p"}, {}, failure="p.py ready: not within 60 s"))
    assert failed == ["lab: p.py ready: not within 60 s"]
    logger = Seen({"p.py": ["a"]}, {"node /p", "service /p/get_loggers"}, {})
    assert differences(case, logger, same) == ["graph: 'service /p/get_loggers' only under ROS 1"]
    monkeypatch.setattr(ros1_oracle, "KNOWN", [("*", "/get_loggers' only under ROS 1", "a reason")])
    assert differences(case, logger, same) == []  # known, with its reason
    assert all(reason for _, _, reason in KNOWN)
