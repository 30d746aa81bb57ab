"""app/cli/grade_services.py without a lab: a URL where nothing listens is said so, status 2
(the grade itself against a lab: tests/e2e/test_grade_services.py)."""

from argparse import Namespace

from app.cli.grade_services import run
from app.serving.launch import free_port


def test_a_lab_that_cannot_be_reached_is_refused_with_status_2(capsys):
    url = f"http://127.0.0.1:{free_port()}"  # nothing listens there
    args = Namespace(url=url, seed=3, quiet=True, out=None, json=None, format="text")
    assert run(args) == 2
    assert f"hri-lab grade-services: cannot reach the lab at {url}" in capsys.readouterr().err
