"""deploy/z2jh-values.yaml, the Zero to JupyterHub values of docs/hosting.md: what the chart's hub
would make of its `hub.config` (the LTI 1.3 authenticator, built from it with every option a real one)
and the single-user pods' settings the lab needs."""

import logging
from pathlib import Path

import yaml
from traitlets.config import Config

VALUES = Path(__file__).resolve().parents[1] / "deploy" / "z2jh-values.yaml"


def test_the_hub_config_builds_the_lti_authenticator(caplog):
    # imported here, not at collection: it imports JupyterHub's app (2.1 s of CPU in every pytest worker)
    from ltiauthenticator.lti13.auth import LTI13Authenticator

    config = yaml.safe_load(VALUES.read_text())["hub"]["config"]
    assert config["JupyterHub"]["authenticator_class"] == "ltiauthenticator.lti13.auth.LTI13Authenticator"
    with caplog.at_level(logging.WARNING):
        authenticator = LTI13Authenticator(config=Config(config))
    assert not [r for r in caplog.records if "not recognized" in r.getMessage()], caplog.text
    lti = config["LTI13Authenticator"]
    assert authenticator.issuer == lti["issuer"]
    assert authenticator.client_id == set(lti["client_id"])
    assert authenticator.config_json_url("/hub/") == "/hub/lti13/config"  # what the LMS registers


def test_the_single_user_pods():
    """JupyterLab (its launcher lists the labs), a volume per student, idle servers culled, and the
    resources marked for the density bench to fill."""
    values = yaml.safe_load(VALUES.read_text())
    user = values["singleuser"]
    assert user["defaultUrl"] == "/lab"
    assert user["storage"]["type"] == "dynamic"
    assert values["cull"]["enabled"]
    assert {"guarantee", "limit"} <= set(user["cpu"]) and {"guarantee", "limit"} <= set(user["memory"])
    assert "From bench/lab_density.py" in VALUES.read_text()  # where the numbers come from
    assert user["cpu"]["guarantee"] <= user["cpu"]["limit"]
    assert 2 / user["cpu"]["guarantee"] >= 2  # the bench's two live labs on a 2-core node fit their guarantees
