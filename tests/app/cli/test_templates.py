"""The starting files `hri-lab template` prints (app/cli/templates/): the lifting nodes hold the
lab's own defaults (one source: LiftingParams), every file is valid Python, and the services
nodes state the rule each handler is graded by."""

import ast
import re
import subprocess
import sys
from dataclasses import fields

import pytest

from sim.controllers.interface import LiftingParams

from app.cli.templates import FILES, NOT_IN_NODES, render
from app.grading.services import EXERCISES

APIS = ("rospy", "rclpy", "roslibpy")


def params_of(text: str) -> dict:
    """The PARAMS literal a printed node assigns at module level."""
    for node in ast.parse(text).body:
        if isinstance(node, ast.Assign) and [t.id for t in node.targets if isinstance(t, ast.Name)] == ["PARAMS"]:
            return ast.literal_eval(node.value)
    raise AssertionError("no PARAMS = {...} in the printed node")


@pytest.mark.parametrize("api", APIS)
def test_a_lifting_node_holds_the_labs_defaults(api):
    printed = params_of(render("node", api))
    lab = LiftingParams()
    expected = {f.name: getattr(lab, f.name) for f in fields(lab) if f.name not in NOT_IN_NODES}
    assert printed == expected
    assert printed["alpha"] == lab.alpha == 0.5  # the drift issue 34 found: the nodes said 0.8


@pytest.mark.parametrize("api", APIS)
def test_every_parameter_a_node_reads_is_in_its_params(api):
    text = render("node", api)
    read = set(re.findall(r'(?:PARAMS|\bp)\["(\w+)"\]', text))
    assert read and read <= set(params_of(text)), read - set(params_of(text))


def test_a_file_without_its_marker_is_refused(tmp_path, monkeypatch):
    import app.cli.templates as templates

    (tmp_path / "lifting_rospy.py").write_text("PARAMS = {'alpha': 0.8}\n")
    monkeypatch.setattr(templates, "__file__", str(tmp_path / "__init__.py"))
    with pytest.raises(RuntimeError, match="@lab-defaults"):
        render("node", "rospy")


@pytest.mark.parametrize(("kind", "api"), sorted(FILES))
def test_every_template_is_python(kind, api):
    compile(render(kind, api), f"{kind}_{api}.py", "exec")


@pytest.mark.parametrize("api", APIS)
def test_each_services_handler_states_its_grading_rule(api):
    tree = ast.parse(render("services", api))
    docs = {
        f.name: ast.get_docstring(f) or ""
        for f in ast.walk(tree)
        if isinstance(f, ast.FunctionDef) and f.name != "main"
    }
    for exercise in EXERCISES:
        handler = exercise.service.strip("/")
        assert "Graded:" in docs.get(handler, ""), (api, handler)


def test_the_rospy_handlers_return_what_rospy_takes():
    """A bare list is read by rospy as the response's fields: a one-field list response must be
    returned as its Response (or a dict), never as the list."""
    tree = ast.parse(render("services", "rospy"))
    for function in (f for f in tree.body if isinstance(f, ast.FunctionDef)):
        for node in ast.walk(function):
            if isinstance(node, ast.Return) and node.value is not None:
                value = node.value
                bare_list = isinstance(value, ast.List) or (
                    isinstance(value, ast.BinOp) and isinstance(value.left, ast.List)
                )
                assert not bare_list, f"{function.name} returns a bare list: {ast.unparse(value)}"
    assert "a bare list" in (ast.get_docstring(tree) or "")  # the rule, where a student reads it


def test_printing_the_controller_template_loads_no_compiled_kernel():
    """`hri-lab template` prints a file: numba, which the built-in controllers' kernels need (~1.3 s
    of CPU to import), is not loaded for it (sim/controllers/plugin.py imports the built-ins where
    a factory of them is asked for)."""
    script = (
        "import runpy, sys\n"
        "sys.argv = ['hri-lab', 'template']\n"
        "try:\n"
        "    runpy.run_module('app.cli', run_name='__main__')\n"
        "except SystemExit as stop:\n"
        "    assert not stop.code, stop.code\n"
        "print('numba loaded' if 'numba' in sys.modules else 'numba not loaded', file=sys.stderr)\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "class CooperativeLifting" in done.stdout
    assert done.stderr.strip().endswith("numba not loaded"), done.stderr
