"""The built-in SP controller wrapped as a plug-in file (what a perfect submission does)."""

from sim.controllers.sp import SPController


class CooperativeLifting(SPController):
    pass
