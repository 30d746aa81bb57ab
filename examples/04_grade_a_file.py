"""Grade a controller file from Python, as `hri-lab grade FILE` does: the file runs sandboxed (its
own process under bubblewrap), the battery feeds it wrenches drawn from the seed and judges it.

    python examples/04_grade_a_file.py                  # the template's probes (seconds)
    python examples/04_grade_a_file.py my_controller.py --full   # probes, the nine trials, robustness
"""

import json
import sys

from sim.controllers import template
from sim.controllers.plugin import PluginFactory

from app.grading.battery import grade

files = [a for a in sys.argv[1:] if not a.startswith("--")]
path = files[0] if files else template.__file__
sections = ("probe", "trial", "robustness") if "--full" in sys.argv else ("probe",)

report = grade(PluginFactory(path), path, seed=0, jobs=2, sections=sections)
print(report.text())
# what Gradescope reads (results.json): one test per item
print(json.dumps(report.gradescope()["tests"][0], indent=2))
