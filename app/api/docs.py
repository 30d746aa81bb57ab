"""/docs (Swagger UI) and /redoc served offline: their scripts and styles come from the pinned
fastapi-offline package (installed with the app), never from a CDN."""

from pathlib import Path

import fastapi_offline
from fastapi import FastAPI
from fastapi.openapi.docs import get_redoc_html, get_swagger_ui_html
from fastapi.responses import HTMLResponse, Response
from fastapi.staticfiles import StaticFiles

ASSETS = Path(fastapi_offline.__file__).resolve().parent / "static"
ASSETS_URL = "/docs-assets"
# the pages name the schema and their assets relative to themselves (/docs -> openapi.json): they work at
# / and under a JupyterHub's prefix (/user/NAME/hri-lab/docs)
RELATIVE_ASSETS = ASSETS_URL.lstrip("/")
REDOC_LOGO = "https://cdn.redoc.ly/redoc/logo-mini.svg"  # ReDoc's side-menu logo: from the server instead


def add_offline_docs(app: FastAPI) -> None:
    """Routes /docs and /redoc (the app is made with docs_url=None, redoc_url=None); the schema
    they show is app/api/openapi.py's."""
    app.mount(ASSETS_URL, StaticFiles(directory=ASSETS), name="docs-assets")

    @app.get("/docs", include_in_schema=False)
    def swagger() -> HTMLResponse:
        return get_swagger_ui_html(
            openapi_url=str(app.openapi_url).lstrip("/"),
            title=f"{app.title} - API docs",
            swagger_js_url=f"{RELATIVE_ASSETS}/swagger-ui-bundle.js",
            swagger_css_url=f"{RELATIVE_ASSETS}/swagger-ui.css",
            swagger_favicon_url=f"{RELATIVE_ASSETS}/favicon.png",
        )

    redoc_js = (
        (ASSETS / "redoc.standalone.js").read_text(encoding="utf-8").replace(REDOC_LOGO, f"{ASSETS_URL}/favicon.png")
    )

    @app.get("/redoc.js", include_in_schema=False)
    def redoc_script() -> Response:
        return Response(redoc_js, media_type="text/javascript")

    @app.get("/redoc", include_in_schema=False)
    def redoc() -> HTMLResponse:
        return get_redoc_html(
            openapi_url=str(app.openapi_url).lstrip("/"),
            title=f"{app.title} - API reference",
            redoc_js_url="redoc.js",
            redoc_favicon_url=f"{RELATIVE_ASSETS}/favicon.png",
            with_google_fonts=False,
        )
