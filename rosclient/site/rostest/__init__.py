"""rostest's Python entry points for a test node: `rostest.rosrun(package, test_name, TestCase)` (a
node's unittest) and `rostest.run(...)` (one that needs no node). The tests run with unittest's
TextTestRunner, as rostest's `--text` mode runs them (no XML result file: the lab's programs report
on their output); the program ends with exit status 1 when a test failed."""

from __future__ import annotations

import sys
import unittest
from typing import Any


def _suite(test: Any) -> unittest.TestSuite:
    loader = unittest.TestLoader()
    if isinstance(test, str):
        return loader.loadTestsFromName(test)
    if isinstance(test, unittest.TestSuite):
        return test
    return loader.loadTestsFromTestCase(test)


def rosrun(package: str, test_name: str, test: Any, sysargs: list[str] | None = None) -> None:
    """Run a node's tests; the node is shut down after them, as rostest does."""
    result = unittest.TextTestRunner(stream=sys.stdout, verbosity=2).run(_suite(test))
    import rospy

    rospy.signal_shutdown("test complete")
    if not result.wasSuccessful():
        sys.exit(1)


def run(package: str, test_name: str, test: Any, sysargs: list[str] | None = None) -> None:
    """Run tests that need no node."""
    result = unittest.TextTestRunner(stream=sys.stdout, verbosity=2).run(_suite(test))
    if not result.wasSuccessful():
        sys.exit(1)


unitrun = run

__all__ = ["rosrun", "run", "unitrun"]
