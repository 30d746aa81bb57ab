"""Schemathesis against the app's own OpenAPI schema, on a live server: bounded number of cases
per operation (a longer run: bench/fuzz.py). Zero 5xx; every refusal is a 422 that names a field
(or a parameter reason)."""
import httpx
import pytest
import schemathesis
from hypothesis import HealthCheck, given, settings

from app.launch import running_server


@pytest.fixture(scope="module")
def api_schema():
    with running_server("--view", "none") as server:
        # the experiment action starts worker processes of whole trials: fuzzed elsewhere, not here
        yield schemathesis.openapi.from_url(f"{server.url}/openapi.json").exclude(path_regex="run_experiment"), server.url


def check(case, response) -> None:
    assert response.status_code < 500, f"{case.method} {case.formatted_path}: {response.status_code} {response.text[:300]}"
    if response.status_code == 422:
        body = response.json()
        if isinstance(body.get("detail"), list):
            assert all(error.get("loc") for error in body["detail"]), body
        else:
            assert body.get("reason") or body.get("detail"), body


def fuzz(api_schema, base_url: str, max_examples: int) -> int:
    """Every operation of the schema, `max_examples` generated cases each; returns the count."""
    calls = 0
    for result in api_schema.get_all_operations():
        operation = result.ok()

        @given(case=operation.as_strategy())
        @settings(max_examples=max_examples, deadline=None, suppress_health_check=list(HealthCheck), database=None)
        def run(case):
            nonlocal calls
            response = case.call(timeout=30)
            calls += 1
            check(case, response)
            if case.path.endswith("/goals") and response.status_code == 202:  # do not leave goals running
                httpx.post(f"{base_url}{case.formatted_path}/{response.json()['goal_id']}/cancel")

        run()
    return calls


def test_api_fuzz(api_schema):
    assert fuzz(*api_schema, max_examples=15) > 100
