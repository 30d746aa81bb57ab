"""The built-in SP controller wrapped as a plug-in file (what a perfect submission does)."""
from sim.sp_controller import SPController


class CooperativeLifting(SPController):
    pass
