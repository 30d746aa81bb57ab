"""bench/roslibjs_suite.py without roslibjs (CI fetches nothing): vitest's JSON report read into one
row a test, a file that failed before its tests ran counted as a failure."""

from bench.ros_corpus import load_manifest
from bench.roslibjs_suite import NODES, SETUP, results_of


def test_vitests_report_gives_each_test_its_status_and_the_first_line_of_its_failure():
    report = {
        "testResults": [
            {
                "name": "/r/test/examples/fibonacci.example.js",
                "assertionResults": [
                    {
                        "fullName": "Fibonacci Example Fibonacci",
                        "status": "failed",
                        "failureMessages": ["Error: Test timed out in 8000ms.\n    at x"],
                    }
                ],
            },
            {
                "name": "/r/test/examples/params.examples.js",
                "assertionResults": [
                    {"fullName": "Param setting Param.get", "status": "passed", "failureMessages": []}
                ],
            },
            {"name": "/r/test/service.test.js", "assertionResults": [], "message": "EISDIR: illegal operation\nmore"},
        ]
    }
    assert results_of(report) == [
        ("fibonacci.example.js: Fibonacci Example Fibonacci", "failed", "Error: Test timed out in 8000ms."),
        ("params.examples.js: Param setting Param.get", "passed", ""),
        ("service.test.js: (the file)", "failed", "EISDIR: illegal operation"),
    ]


def test_the_setups_nodes_are_programs_of_the_corpus_or_here():
    listed = {(p.repo, p.commit) for p in load_manifest()}
    for checkout, path, _, workspace in SETUP:
        for key in (checkout, workspace):
            assert key is None or key in listed, key
        assert checkout is not None or (NODES / path).is_file()
