"""Run one trial of the lab's experiment headless (faster than real time): the calm participant
lifts and carries the box with the robot running the SP controller.

No server needed: python examples/03_run_a_trial.py
"""

from sim.controllers.sp import SPController
from sim.person.participants import PARTICIPANTS
from sim.procedures.trial import Trial

trial = Trial(PARTICIPANTS["calm"], seed=0, controller=SPController())
result = trial.run()

print(f"success: {result.success} {result.reason}")
print(
    f"time: {result.duration:.1f} s, f_n {result.f_n_min:.1f}..{result.f_n_max:.1f} N, "
    f"max |f_t|/(mu f_n) {result.max_friction_ratio:.2f}, slip in the palm {result.slip * 1000:.1f} mm"
)
box = trial.world.box.position
print(f"the box ended at ({box[0]:.3f}, {box[1]:.3f}, {box[2]:.3f}) m")
