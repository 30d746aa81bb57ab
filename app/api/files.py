"""Files the lab made: live recordings (`GET /recordings`, `GET /recordings/NAME` downloads the
MCAP file) and the figures of experiment / comparison goals (`GET /figures/RUN/NAME`, the URLs
an action's result lists). Read-only; names are single path components (no way out of the folder)."""

import re
from pathlib import Path

from fastapi import APIRouter, HTTPException
from fastapi.responses import FileResponse

from app.api.deps import LabDep

NAME = re.compile(r"^[A-Za-z0-9_-][A-Za-z0-9_.-]{0,127}$")
MEDIA = {".mcap": "application/octet-stream", ".png": "image/png", ".svg": "image/svg+xml"}


def _file(folder: Path, *parts: str, disposition: str = "attachment") -> FileResponse:
    """The file, downloaded (attachment) or shown by the browser (inline)."""
    for part in parts:
        if not NAME.match(part):
            raise HTTPException(404, f"no such file: {'/'.join(parts)}")
    path = Path(folder).joinpath(*parts)
    if path.suffix not in MEDIA or not path.is_file():
        raise HTTPException(404, f"no such file: {'/'.join(parts)}")
    return FileResponse(path, media_type=MEDIA[path.suffix], filename=path.name, content_disposition_type=disposition)


router = APIRouter(tags=["files"])


@router.get("/recordings", summary="Recordings of the live lab (MCAP files of /start_recording)")
def recordings(lab: LabDep) -> list[dict]:
    folder = Path(lab.recordings_dir)
    files = sorted(folder.glob("*.mcap")) if folder.is_dir() else []
    active = lab.recorder.path if lab.recorder is not None and lab.recorder.running else None
    return [{"name": p.name, "bytes": p.stat().st_size, "recording": p == active} for p in files]


@router.get("/recordings/{name}", summary="Download a recording (open it in Foxglove or with hri-lab play)")
def recording(name: str, lab: LabDep) -> FileResponse:
    return _file(lab.recordings_dir, name)


@router.get("/figures/{run}/{name}", summary="A figure of an experiment or comparison goal (PNG, SVG)")
def figure(run: str, name: str, lab: LabDep) -> FileResponse:
    return _file(lab.figures_dir, run, name, disposition="inline")  # the page's thumbnails open in a tab
