"""bench/suite_time.py, the plugin that tells where the suite's time goes: each file's tests,
setup, wall and CPU seconds (with its children's and the worker's own) in the table, the longest file first, and the JSON."""

import json
import os
import sys
from pathlib import Path

from sim.controllers.sandbox.watch import stat_ticks

from bench.suite_time import SAMPLE_PERIOD_S, busy_share, program_kind

ROOT = Path(__file__).resolve().parents[2]

pytest_plugins = ["pytester"]


def test_each_files_wall_setup_and_cpu_are_told_longest_first(pytester, monkeypatch, tmp_path):
    pytester.makepyfile(
        test_slow="""
        import subprocess
        import sys
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

        def test_a_child_burns_cpu():
            burn = "import time\\nt = time.process_time()\\nwhile time.process_time() - t < 0.3: pass"
            subprocess.run([sys.executable, "-c", burn], check=True)
        """,
        test_quick="""
        def test_nothing():
            pass
        """,
    )
    out = tmp_path / "times.json"
    monkeypatch.setenv("HRI_LAB_SUITE_TIME", str(out))
    for table in ("HRI_LAB_SUITE_PROGRAMS", "HRI_LAB_SUITE_CORES"):  # the file table alone, whatever runs this test
        monkeypatch.delenv(table, raising=False)
    result = pytester.runpytest("-p", "bench.suite_time", "-p", "no:cacheprovider")
    result.assert_outcomes(passed=4)
    lines = result.outlines
    header = lines.index(next(line for line in lines if line.startswith("suite time by file: 2 files")))
    assert lines[header + 1].split() == ["wall", "s", "setup", "s", "CPU", "s", "own", "s", "tests", "file"]
    assert lines[header + 2].endswith("test_slow.py")
    assert lines[header + 3].endswith("test_quick.py")
    times = json.loads(out.read_text())
    slow = times["test_slow.py"]
    assert slow["tests"] == 3
    assert slow["setup_s"] >= 0.3
    assert slow["wall_s"] >= slow["setup_s"] + 0.4
    assert slow["own_cpu_s"] >= 0.4  # the loop's CPU
    assert slow["cpu_s"] >= slow["own_cpu_s"] + 0.3  # and the child's, which the worker's own leaves out
    assert times["test_quick.py"]["tests"] == 1


def test_a_process_is_named_by_its_program():
    assert program_kind(["/v/bin/python", "-m", "app.cli", "serve", "--port", "1"]) == "hri-lab serve"
    assert program_kind(["/v/bin/python", "/v/bin/hri-lab", "grade", "a.py"]) == "hri-lab grade"
    assert program_kind(["/v/bin/python", "-m", "rosclient.boot", "talker.py"]) == "student program (hri-lab run)"
    assert program_kind(["/v/bin/python", "/v/bin/hri-lab", "run", "talker.py"]) == "student program (hri-lab run)"
    assert program_kind(["bwrap", "--die-with-parent", "python", "-m", "sim.controllers.sandbox.zygote"]) == (
        "sandboxed controller"
    )
    assert program_kind(["/usr/lib/chromium/chromium", "--type=gpu-process"]) == "chromium"
    assert program_kind(["python", "-u", "-c", "import sys;exec(eval(sys.stdin.readline()))"]) == "pytest worker"
    assert program_kind(["/usr/bin/sleep", "1"]) == "sleep"
    lab = ["/v/bin/python", "/v/bin/hri-lab", "serve"]
    assert program_kind(lab, "hri-lab-sim") == "hri-lab-sim (hri-lab serve)"  # a lab's fork, by its name
    assert program_kind(["python", "-m", "pytest"], "hri-lab-camera") == "hri-lab-camera (pytest worker)"
    forked = ["/v/bin/python", "-m", "tests.lab_zygote", "5"]  # the tests' zygote (tests/lab_zygote.py)
    assert program_kind(forked, "python3") == "hri-lab serve"  # itself
    assert program_kind(forked, "serve") == "hri-lab serve"  # a lab it forked, named by its command
    assert program_kind(forked, "grade") == "hri-lab grade"  # a command it forked
    assert program_kind(forked, "hri-lab-sim") == "hri-lab-sim (hri-lab serve)"
    gradescope = ["/tmp/pytest-of-root/pytest-3/popen-gw0/gradescope0/autograder/hri-lab/bin/python", "-m"]
    assert program_kind([*gradescope, "app.grading.gradescope"]) == "Gradescope run (run_autograder)"  # not pytest's
    assert program_kind(["python", "-m", "app.grading.similarity", "out", "0.5"]) == "similarity report (copydetect)"
    assert program_kind(["/v/bin/python", "/v/bin/pytest", "-q"]) == "pytest worker"
    assert program_kind(["/v/bin/python", "-mpytest", "--basetemp=/tmp/x"]) == "pytest worker"


def test_the_cpu_of_every_descendant_is_told_by_program(pytester, monkeypatch):
    """A grandchild that burns CPU and is never waited for by the test (its parent exits first):
    the file table cannot see it, the program table does."""
    pytester.makepyfile(
        test_child="""
        import subprocess, sys

        BURN = "import time; s = time.process_time()\\nwhile time.process_time() - s < 1.0: pass"

        def test_spawns():
            code = f"import subprocess, sys; subprocess.run([sys.executable, '-c', {BURN!r}])"
            subprocess.run([sys.executable, "-c", code], check=True)
        """
    )
    monkeypatch.setenv("HRI_LAB_SUITE_PROGRAMS", "1")
    monkeypatch.delenv("HRI_LAB_SUITE_CORES", raising=False)  # the program table alone, whatever runs this test
    monkeypatch.setenv("PYTHONPATH", str(ROOT))  # the plugin, from this checkout
    result = pytester.runpytest_subprocess("-p", "bench.suite_time", "-p", "no:cacheprovider")
    result.assert_outcomes(passed=1)
    lines = result.outlines
    header = lines.index(next(line for line in lines if line.startswith("CPU by program: ")))
    assert lines[header + 1].split() == ["CPU", "s", "procs", "program"]
    end = next(i for i in range(header, len(lines)) if lines[i].startswith("the run"))
    rows = {row.split(None, 2)[2]: (float(row.split()[0]), int(row.split()[1])) for row in lines[header + 2 : end]}
    burned, processes = rows[os.path.basename(sys.executable)]
    assert processes == 2
    assert burned >= 1.0 - 2 * SAMPLE_PERIOD_S  # the last reading may come up to a period before its end


def test_the_cores_busy_share_is_read_from_proc_stat_lines():
    before = stat_ticks("cpu  100 0 50 800 50 0 0 0 0 0")  # user nice system idle iowait irq softirq steal ...
    after = stat_ticks("cpu  250 0 100 900 50 0 0 0 0 0")  # 200 ticks busy, 100 idle
    assert before == (150, 1000)
    assert busy_share(before, after) == 200 / 300
    assert busy_share(after, after) == 0.0  # no tick between the two: nothing to say


def test_the_cores_line_and_each_workers_end_are_told(pytester, monkeypatch):
    pytester.makepyfile(
        test_burn="""
        import time

        def test_burns_cpu():
            start = time.process_time()
            while time.process_time() - start < 1.5:
                pass
        """
    )
    monkeypatch.setenv("HRI_LAB_SUITE_CORES", "1")
    monkeypatch.delenv("HRI_LAB_SUITE_PROGRAMS", raising=False)
    result = pytester.runpytest("-p", "bench.suite_time", "-p", "no:cacheprovider")
    result.assert_outcomes(passed=1)
    cores = next(line for line in result.outlines if line.startswith("the cores busy, each 20 s: "))
    windows, whole = cores.removeprefix("the cores busy, each 20 s: ").split(" %; ")
    assert 0 < float(windows.split()[0]) <= 100  # the test's own loop kept a core busy
    assert whole.endswith(" % over the run") and 0 < float(whole.split()[0]) <= 100
    ended = next(line for line in result.outlines if line.startswith("each worker's last test ended: "))
    assert ended.startswith("each worker's last test ended: the run at ")  # no xdist: the run's one process
