"""/docs (Swagger UI) and /redoc served offline: their scripts and styles come from the pinned
fastapi-offline package (installed with the app), never from a CDN."""
from pathlib import Path

import fastapi_offline
from fastapi import FastAPI
from fastapi.openapi.docs import get_redoc_html, get_swagger_ui_html
from fastapi.responses import HTMLResponse, Response
from fastapi.staticfiles import StaticFiles

from app.ros.messages import INT64_MAX, INT64_MIN

ASSETS = Path(fastapi_offline.__file__).resolve().parent / "static"
ASSETS_URL = "/docs-assets"
REDOC_LOGO = "https://cdn.redoc.ly/redoc/logo-mini.svg"  # ReDoc's side-menu logo: from the server instead


def add_offline_docs(app: FastAPI) -> None:
    """Routes /docs and /redoc (the app is made with docs_url=None, redoc_url=None), and an
    OpenAPI schema whose integer bounds are exact."""
    generate = app.openapi

    def openapi() -> dict:
        if app.openapi_schema is None:
            app.openapi_schema = exact_integer_bounds(generate())
        return app.openapi_schema

    app.openapi = openapi
    app.mount(ASSETS_URL, StaticFiles(directory=ASSETS), name="docs-assets")

    @app.get("/docs", include_in_schema=False)
    def swagger() -> HTMLResponse:
        return get_swagger_ui_html(
            openapi_url=app.openapi_url, title=f"{app.title} - API docs",
            swagger_js_url=f"{ASSETS_URL}/swagger-ui-bundle.js", swagger_css_url=f"{ASSETS_URL}/swagger-ui.css",
            swagger_favicon_url=f"{ASSETS_URL}/favicon.png",
        )

    redoc_js = (ASSETS / "redoc.standalone.js").read_text(encoding="utf-8").replace(REDOC_LOGO, f"{ASSETS_URL}/favicon.png")

    @app.get("/redoc.js", include_in_schema=False)
    def redoc_script() -> Response:
        return Response(redoc_js, media_type="text/javascript")

    @app.get("/redoc", include_in_schema=False)
    def redoc() -> HTMLResponse:
        return get_redoc_html(openapi_url=app.openapi_url, title=f"{app.title} - API reference",
                              redoc_js_url="/redoc.js",
                              redoc_favicon_url=f"{ASSETS_URL}/favicon.png", with_google_fonts=False)


def exact_integer_bounds(node):
    """FastAPI's OpenAPI model stores bounds as floats: int64's 2^63 - 1 would read 2^63 (and
    9.223372036854776e+18). Integer bounds become ints again, +-2^63 those of int64."""
    if isinstance(node, dict):
        if node.get("type") == "integer":
            for key in ("minimum", "maximum"):
                value = node.get(key)
                if isinstance(value, float) and value.is_integer():
                    node[key] = max(INT64_MIN, min(INT64_MAX, int(value)))
        for value in node.values():
            exact_integer_bounds(value)
    elif isinstance(node, list):
        for value in node:
            exact_integer_bounds(value)
    return node
