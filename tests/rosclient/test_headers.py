"""rosclient/headers.py's `lab_headers`: what a client sends the lab, on a laptop and behind a JupyterHub."""

from rosclient.headers import lab_headers


def test_on_a_laptop_the_labs_token_is_a_bearer(monkeypatch):
    monkeypatch.delenv("JUPYTERHUB_API_TOKEN", raising=False)
    assert lab_headers("http://127.0.0.1:8000", None) == {}
    assert lab_headers("http://127.0.0.1:8000", "t" * 16) == {"Authorization": "Bearer " + "t" * 16}


def test_behind_a_hub_the_students_hub_token_goes_first(monkeypatch):
    """Under the student's server's prefix, the hub reads Authorization: the lab's token moves to
    X-HRI-Lab-Token; any other URL never gets the hub token."""
    monkeypatch.setenv("JUPYTERHUB_API_TOKEN", "hub-token")
    monkeypatch.setenv("JUPYTERHUB_SERVICE_PREFIX", "/user/ada/")
    lab = "http://127.0.0.1:8888/user/ada/hri-lab/"
    assert lab_headers(lab, None) == {"Authorization": "token hub-token"}
    assert lab_headers(lab, "t" * 16) == {"Authorization": "token hub-token", "X-HRI-Lab-Token": "t" * 16}
    assert lab_headers("http://127.0.0.1:8000", None) == {}
    assert lab_headers("http://127.0.0.1:8888/user/bob/hri-lab/", None) == {}
