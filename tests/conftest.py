import pytest


@pytest.fixture(scope="module")
def client():
    """The real app with its live 1 kHz loop, driven over HTTP (httpx via the TestClient)."""
    from fastapi.testclient import TestClient

    from app.api.app import create_app

    with TestClient(create_app()) as c:
        yield c


@pytest.fixture
def lab(client):
    return client.app.state.lab
