"""The lab's parameters (app/lab/params.py): each declared once, its value read and applied in the
simulation process by a command of app/lab/commands.py."""

from app.lab.params import LAB_PARAMETERS
from app.runtime.loop import only_reads


def test_every_parameters_read_only_reads_the_world():
    """A parameter's read is marked `reads_world` (app/runtime/loop.py): the page and a node read
    parameters on a schedule, and a read must leave an idle lab idle; its apply is not marked (a
    new value may set the robot going)."""
    for parameter in LAB_PARAMETERS:
        if parameter.read is not None:
            assert only_reads(parameter.read), parameter.name
        if parameter.apply is not None:
            assert not only_reads(parameter.apply), parameter.name
