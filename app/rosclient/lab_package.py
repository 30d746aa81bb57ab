"""The lab's own interface package, `hri_lab`: the .srv and .action texts of the lab's declarations
(app/lab), which a program imports as `from hri_lab.srv import DivideInts`. Apart from the parser
(interfaces.py), which the lab's server uses too, so that the two import each other in no order."""

from app.rosclient.interfaces import LAB_PACKAGE


def lab_definitions() -> dict[str, dict[str, str]]:
    """kind -> name -> text of the lab's services and actions, from their declarations. The lab's
    modules are imported here, when a program first imports from `hri_lab`, not when it starts."""
    from app.lab.actions import ACTIONS
    from app.lab.services import SERVICES

    return {
        "msg": {},
        "srv": {s.type.split("/")[-1]: s.srv for s in SERVICES if s.type.startswith(LAB_PACKAGE + "/")},
        "action": {a.type.split("/")[-1]: a.definition for a in ACTIONS if a.type.startswith(LAB_PACKAGE + "/")},
    }
