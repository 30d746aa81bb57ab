"""A file that copies the lab's SP instead of importing it: it reads sp.py's text from the `sim`
package the jail shows (read-only, as every student's machine has it) and runs it as its own."""

import pathlib

import sim.controllers.interface

_SOURCE = pathlib.Path(sim.controllers.interface.__file__).with_name("sp.py").read_text()
_NAMESPACE: dict = {"__name__": "my_controller"}
exec(compile(_SOURCE, "my_controller.py", "exec"), _NAMESPACE)  # noqa: S102 - the copy is the attack


class CooperativeLifting(_NAMESPACE["SPController"]):
    pass
