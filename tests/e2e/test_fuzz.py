"""Schemathesis against the app's own OpenAPI schema, on a live server, with a bounded number of
cases per operation (the longer run: `python -m bench.fuzz`)."""

import pytest

from tests.e2e.serving import running_server


@pytest.fixture(scope="module")
def server_url():
    with running_server("--view", "none") as server:
        yield server.url


def test_api_fuzz(server_url):
    from bench.fuzz import fuzz  # schemathesis: imported by the worker that runs this, not at every collection

    assert fuzz(server_url, max_examples=15, derandomize=True) > 100
