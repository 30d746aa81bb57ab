"""bench/lab_density.py's pure parts: the counts it tries, what it reads from /proc, and how it
decides that the machine fell behind."""

import os
import re
from pathlib import Path

import pytest

from bench import lab_density as d


def test_doublings_end_at_the_limit():
    assert d.doublings(1) == [1]
    assert d.doublings(8) == [1, 2, 4, 8]
    assert d.doublings(12) == [1, 2, 4, 8, 12]


def test_cpu_ticks_and_parent_from_a_stat_line_whose_command_holds_spaces_and_parens():
    # pid (comm) state ppid pgrp session tty tpgid flags minflt cminflt majflt cmajflt utime stime ...
    line = "4242 (a (b) c) S 17 4242 4242 0 -1 4194304 100 0 0 0 250 75 0 0 20 0 3 0 1000 1 1"
    assert d.cpu_ticks(line) == 325
    assert d.parent_pid(line) == 17


def test_cpu_ticks_of_this_process_grow_with_work():
    stat = Path(f"/proc/{os.getpid()}/stat")
    deadline = d.cpu_ticks(stat.read_text()) + 2
    while d.cpu_ticks(stat.read_text()) < deadline:
        sum(range(10_000))
    assert d.process_tree(os.getpid()) >= {os.getpid()}


def test_descendants_follow_the_tree_and_nothing_else():
    parents = {2: 1, 3: 2, 4: 2, 5: 3, 6: 1, 7: 6}
    assert d.descendants(2, parents) == {2, 3, 4, 5}
    assert d.descendants(5, parents) == {5}


def test_pss_read_from_smaps_rollup():
    text = "00400000-7ffd [rollup]\nRss:               20480 kB\nPss:               12345 kB\nPss_Anon: 1 kB\n"
    assert d.pss_kib(text) == 12345
    assert d.pss_kib("") == 0
    assert d.tree_mib({os.getpid()}) > 1  # this interpreter's own


def health(sim_time, overruns, realtime=False):
    return {"sim_time": sim_time, "overruns": overruns, "lateness_p99_ms": 0.4, "realtime_priority": realtime}


def test_lab_figures_from_two_health_answers():
    ticks = d.CLOCK_TICKS
    f = d.lab_figures(
        health(10.0, 3), health(29.0, 13), 20.0, (0, 10 * ticks), (0, 2 * ticks), lab_mib=500.0, node_mib=60.0
    )
    assert f.rtf == pytest.approx(0.95)
    assert f.periods == 19_000 and f.missed == 10
    assert f.lab_cpu == pytest.approx(50.0) and f.node_cpu == pytest.approx(10.0)
    assert not f.realtime


def test_a_lab_falls_behind_when_slow_or_missing_periods():
    ticks = d.CLOCK_TICKS
    keeping_up = d.lab_figures(health(0, 0), health(10.0, 99), 10.0, (0, ticks), (0, ticks), lab_mib=1, node_mib=1)
    assert not keeping_up.behind()  # 99 of 10,000 periods: under 1 %
    missing = d.lab_figures(health(0, 0), health(10.0, 101), 10.0, (0, ticks), (0, ticks), lab_mib=1, node_mib=1)
    assert missing.behind()
    slow = d.lab_figures(health(0, 0), health(9.0, 0), 10.0, (0, ticks), (0, ticks), lab_mib=1, node_mib=1)
    assert slow.behind()
    s = d.summary(2, [keeping_up, slow])
    assert s["behind"] and s["rtf_min"] == pytest.approx(0.9)
    assert s["cpu_per_student"] == pytest.approx(2 * 100.0 / 10.0)
    assert "normal" in d.row(2, 1, slow) and "0.900" in d.row(2, 1, slow)


def test_the_dashboards_read_what_the_page_reads():
    # every fixed path static/app.js GETs is polled at the page's pace or read once when it opens,
    # and its plots' streams are the bench's (paths built per item are a new item's, read once)
    page = (Path(__file__).resolve().parents[2] / "static" / "app.js").read_text()
    literals = (path.split("?")[0] for path in re.findall(r'api\("GET", [`"](/[^`"]*)', page))
    gets = {path for path in literals if "${" not in path}
    assert gets == set(d.PAGE_POLLS) | d.PAGE_READS_ONCE
    assert not set(d.PAGE_POLLS) & d.PAGE_READS_ONCE
    streams = set(re.findall(r'stream\("(/[^"]+)", (?:RATE_HZ|\d+)', page))
    assert streams == set(d.PAGE_STREAMS)
