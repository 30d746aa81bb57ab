"""app/jupyter_proxy.py: the entry points jupyter-server-proxy reads (pyproject's
`jupyter_serverproxy_servers`), as it reads them. The lab behind a real JupyterHub:
tests/e2e/browser/test_jupyterhub.py."""

import os
from importlib.metadata import entry_points

from app import jupyter_proxy
from app.security import PROXY_HEADER, PROXY_SECRET_ENV


def test_the_launcher_entries_are_installed():
    found = {e.name: e.load() for e in entry_points(group="jupyter_serverproxy_servers") if e.module.startswith("app.")}
    assert found == {"hri-lab": jupyter_proxy.lab, "hri-lab-mobile": jupyter_proxy.mobile}


def test_a_lab_is_served_on_the_proxys_port_with_its_secret(monkeypatch):
    monkeypatch.setenv("HRI_LAB_URL", "")  # recorded, so that what lab() sets is undone after the test
    monkeypatch.delenv("HRI_LAB_URL")
    monkeypatch.delenv("JUPYTERHUB_SERVICE_URL", raising=False)
    monkeypatch.delenv("HRI_LAB_VIEW", raising=False)
    lab, mobile = jupyter_proxy.lab(), jupyter_proxy.mobile()
    assert lab["command"][-7:] == ["serve", "--port", "{port}", "--world", "lifting", "--view", "full"]
    assert mobile["command"][-3] == "mobile"
    monkeypatch.setenv("HRI_LAB_VIEW", "light")  # an instructor's choice for the students' laptops
    assert jupyter_proxy.lab()["command"][-1] == "light"
    assert lab["launcher_entry"]["title"] == "hri-lab"
    assert mobile["launcher_entry"]["title"] == "hri-lab mobile"
    assert not lab["absolute_url"]  # the prefix stripped: the lab's pages are relative
    secret = lab["environment"][PROXY_SECRET_ENV]
    assert len(secret) >= 32
    assert lab["request_headers_override"] == {PROXY_HEADER: secret}
    assert mobile["environment"][PROXY_SECRET_ENV] == secret


def test_the_terminal_is_told_where_the_lab_is(monkeypatch):
    monkeypatch.setenv("HRI_LAB_URL", "")  # recorded, so that what lab() sets is undone after the test
    monkeypatch.delenv("HRI_LAB_URL")
    monkeypatch.setenv("JUPYTERHUB_SERVICE_URL", "http://127.0.0.1:41234/user/ada/")
    jupyter_proxy.lab()
    assert os.environ["HRI_LAB_URL"] == "http://127.0.0.1:41234/user/ada/hri-lab/"
    monkeypatch.setenv("HRI_LAB_URL", "http://127.0.0.1:9000")  # a student's own choice stays
    jupyter_proxy.lab()
    assert os.environ["HRI_LAB_URL"] == "http://127.0.0.1:9000"
