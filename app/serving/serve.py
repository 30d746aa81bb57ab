"""The lab's server: a world's lab built, its parameter file applied, composed with the API,
rosbridge and the view (app/serving/compose.py) and served by uvicorn with the HTTP server's limits
(app/serving/http.py), its URLs printed once the socket is bound. `hri-lab serve` (app/cli/serve.py)
makes its refusals before it imports this module."""

import sys
from pathlib import Path
from typing import Any

import uvicorn

from app.ros.params import ParameterRefused, read_parameter_file
from app.serving.compose import create_app
from app.serving.http import server_config
from app.serving.worlds import DEFAULT, WORLDS
from app.worlds.contract import LabOptions
from app.worlds.port import LabPort


def load_parameter_file(lab: LabPort[Any], path: str) -> None:
    """Apply a `param dump` file at start (the seed's launch file); read-only ones too, as
    parameter overrides can at declaration. Any refusal stops the start with its reason."""
    results = lab.params.load(read_parameter_file(path), force=True)
    failed = [r for r in results if not r["successful"]]
    if failed:
        raise ParameterRefused("; ".join(f"/{r['node']}/{r['name']}: {r['reason']}" for r in failed))


def serve(
    host: str = "127.0.0.1",
    port: int = 8000,
    params_file: str | None = None,
    view: str = "full",
    view_port: int = 8080,
    controller=None,
    token: str | None = None,
    exercises: bool = False,
    output_dir: str = ".",
    world: str | None = None,
    arena_seed: int | None = None,
    replay: bool = False,
) -> int:
    """The lab of `world` built, composed and served on host:port until Ctrl+C (the command's
    refusals, app/cli/serve.py, came first); 0 once it ran, 1 if it could not start."""
    served = WORLDS[world or DEFAULT]
    lab = served.lab(LabOptions(controller=controller, arena_seed=arena_seed))
    lab.recordings_dir, lab.figures_dir = Path(output_dir) / "recordings", Path(output_dir) / "figures"
    if params_file:
        try:
            load_parameter_file(lab, params_file)
        except (OSError, ParameterRefused) as exc:
            print(f"hri-lab: cannot load parameters from {params_file}: {exc}", file=sys.stderr)
            return 2
    app = create_app(
        served, lab, view=view, view_host=host, view_port=view_port, token=token, exercises=exercises, replay=replay
    )
    server = AnnouncingServer(server_config(app, host, port))
    try:
        server.run()
    except KeyboardInterrupt:  # Ctrl+C: the server shut down first (uvicorn, or asyncio's runner, re-raises it)
        pass  # the lab stops as asked: no traceback in the terminal
    return 0 if server.started else 1


class AnnouncingServer(uvicorn.Server):
    """Prints the URLs once the socket is bound (not before: the port may be taken)."""

    async def startup(self, sockets=None) -> None:
        await super().startup(sockets)
        if self.started:
            base = f"http://{self.config.host}:{self.config.port}"
            view = self.config.app.state.view  # type: ignore[union-attr]  # our FastAPI app, not an import string
            print(
                f"hri-lab is running: open {base}/\n"
                f"  API       {base}/services  {base}/params  {base}/topics  {base}/actions\n"
                f"  API docs  {base}/docs  {base}/redoc\n"
                f"  rosbridge ws://{self.config.host}:{self.config.port}/  (roslibpy.Ros('{self.config.host}', {self.config.port}))\n"
                + (f"  3D view   {view.url}\n" if view is not None else "")
                + "Press Ctrl+C to stop.",
                flush=True,
            )
