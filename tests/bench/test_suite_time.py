"""bench/suite_time.py, the plugin that tells where the suite's time goes: each file's tests,
setup, wall and CPU seconds in the table, the longest file first, and the JSON."""

import json

pytest_plugins = ["pytester"]


def test_each_files_wall_setup_and_cpu_are_told_longest_first(pytester, monkeypatch, tmp_path):
    pytester.makepyfile(
        test_slow="""
        import time
        import pytest

        @pytest.fixture
        def slow_setup():
            time.sleep(0.3)

        def test_setup(slow_setup):
            pass

        def test_burns_cpu():
            start = time.process_time()
            while time.process_time() - start < 0.4:
                pass
        """,
        test_quick="""
        def test_nothing():
            pass
        """,
    )
    out = tmp_path / "times.json"
    monkeypatch.setenv("HRI_LAB_SUITE_TIME", str(out))
    result = pytester.runpytest("-p", "bench.suite_time", "-p", "no:cacheprovider")
    result.assert_outcomes(passed=3)
    lines = result.outlines
    header = lines.index(next(line for line in lines if line.startswith("suite time by file: 2 files")))
    assert lines[header + 1].split() == ["wall", "s", "setup", "s", "CPU", "s", "tests", "file"]
    assert lines[header + 2].endswith("test_slow.py")
    assert lines[header + 3].endswith("test_quick.py")
    times = json.loads(out.read_text())
    slow = times["test_slow.py"]
    assert slow["tests"] == 2
    assert slow["setup_s"] >= 0.3
    assert slow["wall_s"] >= slow["setup_s"] + 0.4
    assert slow["cpu_s"] >= 0.4  # the loop's CPU
    assert times["test_quick.py"]["tests"] == 1
