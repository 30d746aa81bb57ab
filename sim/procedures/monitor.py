"""The trial monitor lives beside the world it judges: sim/monitor.py. This name stays only until
sim/procedures/experiment.py and grading.py (being cut into trial, runner and tables) import it from
there; then this file goes."""

from sim.monitor import TrialRules

__all__ = ["TrialRules"]
