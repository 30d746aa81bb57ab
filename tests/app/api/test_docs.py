"""/docs and /redoc work without internet, and what they pre-fill is accepted."""

import re

import pytest

from app.lab.actions import ACTIONS
from app.lab.services import SERVICES


@pytest.mark.parametrize("path", ["/docs", "/redoc"])
def test_docs_pages_load_their_assets_from_the_server(client, path):
    html = client.get(path).text
    assets = re.findall(r'(?:src|href)="([^"]+)"', html) + re.findall(r"url: '([^']+)'", html)
    assert assets and not any(a.startswith(("http:", "https:", "//")) for a in assets), assets
    for asset in assets:
        response = client.get(asset)
        assert response.status_code == 200 and len(response.content) > 1000, asset


def test_int64_bounds_are_exact_in_the_schema(client):
    text = client.get("/openapi.json").text
    assert '"maximum":9223372036854775807' in text.replace(" ", "")
    assert "e+18" not in text
    a = client.get("/openapi.json").json()["components"]["schemas"]["TwoInts"]["properties"]["a"]
    assert (a["minimum"], a["maximum"], a["examples"]) == (-(2**63), 2**63 - 1, [0])


def test_every_prefilled_service_request_is_accepted(client):
    paths = client.get("/openapi.json").json()["paths"]
    for service in SERVICES:
        body = paths[f"/services{service.name}"]["post"].get("requestBody")
        assert body or not service.request.model_fields, f"{service.name}: no request body to pre-fill"
        example = body["content"]["application/json"]["examples"]["example"]["value"] if body else None
        response = client.post(f"/services{service.name}", json=example)
        assert response.status_code == 200, (service.name, example, response.text)
    client.post("/services/reset_simulation")


def test_every_prefilled_goal_is_valid(client):
    paths = client.get("/openapi.json").json()["paths"]
    assert ACTIONS
    for action in ACTIONS:  # validated, not run (an example experiment takes minutes)
        body = paths[f"/actions{action.name}/goals"]["post"].get("requestBody")
        assert body, f"{action.name}: the schema has no goal body to pre-fill"
        action.goal.model_validate(body["content"]["application/json"]["examples"]["example"]["value"])
