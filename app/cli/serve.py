"""`hri-lab serve`: the lab's server on 127.0.0.1 (embedded defaults; optional parameter file)."""
import sys

import uvicorn

from app.api.access import TOKEN_ENV, is_loopback
from app.lab.lab import Lab
from app.ros.params import ParameterRefused
from app.api.app import create_app


def load_parameter_file(lab: Lab, path: str) -> None:
    """Apply a `param dump` file at start (the seed's launch file); read-only ones too, as
    parameter overrides can at declaration. Any refusal stops the start with its reason."""
    with open(path, encoding="utf-8") as handle:
        results = lab.params.load(handle.read(), force=True)
    failed = [r for r in results if not r["successful"]]
    if failed:
        raise ParameterRefused("; ".join(f"/{r['node']}/{r['name']}: {r['reason']}" for r in failed))


def serve(host: str = "127.0.0.1", port: int = 8000, params_file: str | None = None, view: str = "full",
          view_port: int = 8080, controller=None, token: str | None = None) -> int:
    if not is_loopback(host) and not token:
        print(f"hri-lab: binding {host} (not this machine only) needs a token: --token or ${TOKEN_ENV}", file=sys.stderr)
        return 2
    lab = Lab(controller=controller)
    if params_file:
        try:
            load_parameter_file(lab, params_file)
        except (OSError, ParameterRefused) as exc:
            print(f"hri-lab: cannot load parameters from {params_file}: {exc}", file=sys.stderr)
            return 2
    app = create_app(lab, view=view, view_host=host, view_port=view_port, token=token)
    config = uvicorn.Config(app, host=host, port=port, log_level="warning", access_log=False)
    server = AnnouncingServer(config)
    server.run()
    return 0 if server.started else 1


class AnnouncingServer(uvicorn.Server):
    """Prints the URLs once the socket is bound (not before: the port may be taken)."""

    async def startup(self, sockets=None) -> None:
        await super().startup(sockets)
        if self.started:
            base = f"http://{self.config.host}:{self.config.port}"
            view = self.config.app.state.view
            print(
                f"hri-lab is running: open {base}/\n"
                f"  API       {base}/services  {base}/params  {base}/topics  {base}/actions\n"
                f"  API docs  {base}/docs  {base}/redoc\n"
                + (f"  3D view   {view.url}\n" if view is not None else "")
                + "Press Ctrl+C to stop.",
                flush=True,
            )
