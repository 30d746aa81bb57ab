"""Schemathesis against the app's own OpenAPI schema on a live server: generated requests for every
operation, each validated with all of schemathesis' checks (no 5xx, status codes, content types
and bodies as documented, invalid data refused, valid data accepted, ...) and ours (every refusal
a 422 naming a field, or a parameter reason). `make test` runs a bounded number of cases
(tests/e2e/test_fuzz.py); this is the longer run.

    .venv/bin/python -m bench.fuzz [--examples 200]
"""

from __future__ import annotations

import argparse
import time

import httpx
import schemathesis
import schemathesis.config
from hypothesis import HealthCheck, given, settings
from schemathesis.checks import CHECKS, load_all_checks

from app.serving.launch import running_server

load_all_checks()
ALL_CHECKS = CHECKS.get_all()
# a schema-valid service call may still fail: the documented 400 service failure (e.g. a
# least-squares wrench that overflows float64)
CONFIG = schemathesis.config.SchemathesisConfig.from_dict(
    {"checks": {"positive_data_acceptance": {"expected-statuses": ["2xx", "400", "401", "403", "404", "409", "429"]}}}
)


def check(case, response) -> None:
    assert response.status_code < 500, (
        f"{case.method} {case.formatted_path}: {response.status_code} {response.text[:300]}"
    )
    if response.status_code == 422:
        body = response.json()
        if isinstance(body.get("detail"), list):
            assert all(error.get("loc") for error in body["detail"]), body
        else:
            assert body.get("reason") or body.get("detail"), body


def fuzz(base_url: str, max_examples: int, derandomize: bool = False) -> int:
    """Every operation (but the experiment action, which starts whole trials), `max_examples`
    generated cases each; returns the number of requests sent. derandomize: the same cases every
    run (the suite's short run; the long run here draws new ones each time)."""
    schema = schemathesis.openapi.from_url(f"{base_url}/openapi.json", config=CONFIG).exclude(
        path_regex="run_experiment"
    )
    calls = 0
    for result in schema.get_all_operations():
        operation = result.ok()

        @given(case=operation.as_strategy())
        @settings(
            max_examples=max_examples,
            deadline=None,
            suppress_health_check=list(HealthCheck),
            database=None,
            derandomize=derandomize,
        )
        def run(case):
            nonlocal calls
            response = case.call(timeout=30)
            calls += 1
            check(case, response)
            case.validate_response(response, checks=ALL_CHECKS)
            if case.path.endswith("/goals") and response.status_code == 202:  # do not leave goals running
                httpx.post(f"{base_url}{case.formatted_path}/{response.json()['goal_id']}/cancel")

        run()
    return calls


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--examples", type=int, default=200)
    args = parser.parse_args()
    with running_server("--view", "none") as server:
        started = time.perf_counter()
        calls = fuzz(server.url, args.examples)
        health = httpx.get(f"{server.url}/health").json()
    print(
        f"fuzz: {calls} generated requests in {time.perf_counter() - started:.0f} s: no 5xx, every refusal names "
        f"its field; loop alive {health['loop_alive']}, step errors {health['step_errors']}"
    )


if __name__ == "__main__":
    main()
