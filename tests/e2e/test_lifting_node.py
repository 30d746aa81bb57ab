"""Exercise 16 in the live lab: the lifting node from the template (filled in with the SP law)
carries the calm participant's box, driving the robot only through rosbridge (F_ext in, Twist
commands out). Real time: ~20 s. The command period is raised to 5 s (tests/e2e/lifting.py)."""

import subprocess
import sys
from pathlib import Path

from tests.e2e.lifting import carry_the_box, slow_commands
from tests.e2e.serving import running_server

NODE = Path(__file__).resolve().parents[1] / "nodes" / "lifting_solution.py"


def test_the_lifting_node_carries_the_box():
    with running_server("--view", "none") as lab:
        slow_commands(lab.url)
        node = subprocess.Popen(
            [sys.executable, str(NODE), "--port", str(lab.port)],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
        )
        try:
            assert node.stdout.readline().startswith("node ready")
            # held between plate and palm to the end: carried, not dropped. How far the box slid in the
            # palm on the way depends on how promptly the node's process gets a core (the built-in SP
            # at 1 kHz: 4 mm; a node on a loaded 2-core machine: 3.5-9 cm), so it is reported, not asserted
            carry_the_box(lab.url, "f_n_max = 15 N.", timeout_s=120)
        finally:
            node.terminate()
            node.wait(timeout=10)
            node.stdout.close()
