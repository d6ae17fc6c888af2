"""The offline checker's routes: the page at /check/ (a service worker at /check/sw.js controls only
/check/...), its scripts and vendored libraries, the worker and the web app manifest.

The page is the one place with JavaScript, so it alone gets a Content-Security-Policy that allows
scripts and workers from this origin; every other page keeps `script-src 'none'` (app/web/headers.py).
"""

from __future__ import annotations

import hashlib
import json
from functools import cache
from pathlib import Path
from typing import Any

from fastapi import APIRouter
from starlette.requests import Request
from starlette.responses import FileResponse, RedirectResponse, Response

from app.checker.words import checker_words
from app.config import get_settings
from app.errors import NotFound
from app.i18n.active import use_locale
from app.i18n.locales import LOCALES
from app.web.templating import SERVICE_NAME, render

STATIC = Path(__file__).resolve().parent / "static"
MEDIA_TYPES = {".js": "text/javascript", ".css": "text/css", ".png": "image/png", ".LICENSE": "text/plain"}
CHECK_CSP = (
    "default-src 'self'; img-src 'self' data: blob:; style-src 'self'; script-src 'self'; "
    "worker-src 'self'; connect-src 'self'; media-src 'self' blob: mediastream:; manifest-src 'self'; "
    "object-src 'none'; base-uri 'none'; form-action 'self'; frame-ancestors 'none'"
)
# Revalidated every time (a 304 when unchanged): the service worker keeps the offline copies.
REVALIDATE = {"Cache-Control": "no-cache"}

router = APIRouter(include_in_schema=False)


@cache
def static_files() -> dict[str, Path]:
    """The files under /check/static/ by their name there (and only those: no path walks out)."""
    return {
        path.relative_to(STATIC).as_posix(): path
        for path in sorted(STATIC.rglob("*"))
        if path.is_file() and path.suffix in MEDIA_TYPES and path.name != "sw.js"
    }


@cache
def version() -> str:
    """A digest of every file the worker keeps and of the page's words: a new one makes it refresh all."""
    digest = hashlib.sha256()
    for name, path in static_files().items():
        digest.update(name.encode() + b"\0" + path.read_bytes())
    digest.update((STATIC / "sw.js").read_bytes())
    for locale in LOCALES:  # the page's words in every language: a changed translation refreshes too
        with use_locale(locale):
            digest.update(json.dumps(checker_words(), sort_keys=True).encode())
    template = Path(__file__).resolve().parents[2] / "templates" / "checker" / "check.html"
    if template.is_file():
        digest.update(template.read_bytes())
    return digest.hexdigest()[:16]


@router.get("/check")
def check_redirect() -> RedirectResponse:
    """The page lives at /check/, inside its service worker's scope."""
    return RedirectResponse("/check/", status_code=308)


@router.get("/check/")
def check_page(request: Request) -> Response:
    """The offline checker: read a paper's QR code and decide it on the device against the trust bundle."""
    settings = get_settings()
    response = render(
        request,
        "checker/check.html",
        {
            "words": checker_words(),
            "issuing_authority": settings.issuing_authority,
            "version": version(),
            "files": [f"/check/static/{name}" for name in static_files() if not name.endswith(".LICENSE")],
        },
    )
    response.headers["Content-Security-Policy"] = CHECK_CSP
    return response


@router.get("/check/sw.js")
def service_worker() -> Response:
    """The service worker: keeps the page, its files and the newest bundle; its version names its cache."""
    keep = ["/check/", "/check/manifest.webmanifest", "/static/app.css"]
    keep += [f"/check/static/{name}" for name in static_files()]
    head = f"const VERSION = {json.dumps(version())};\nconst KEEP = {json.dumps(keep)};\n"
    body = head + (STATIC / "sw.js").read_text()
    return Response(body, media_type="text/javascript", headers=REVALIDATE)


@router.get("/check/manifest.webmanifest")
def manifest() -> Response:
    """The web app manifest: the checker installs as an app of its own, opening at /check/."""
    body: dict[str, Any] = {
        "name": f"{SERVICE_NAME}: roadside check",
        "short_name": "Check",
        "description": "Check a tricycle's stability certificate offline, from its QR code.",
        "id": "/check/",
        "start_url": "/check/",
        "scope": "/check/",
        "display": "standalone",
        "background_color": "#ffffff",
        "theme_color": "#0b0c0c",
        "icons": [
            {"src": f"/check/static/icon-{size}.png", "sizes": f"{size}x{size}", "type": "image/png"}
            for size in (192, 512)
        ],
    }
    return Response(json.dumps(body), media_type="application/manifest+json", headers=REVALIDATE)


@router.get("/check/static/{name:path}")
def static_file(name: str) -> FileResponse:
    """One of the page's files, by its name under app/checker/static/."""
    path = static_files().get(name)
    if path is None:
        raise NotFound(f"no file {name!r} on the check page")
    suffix = ".LICENSE" if path.name.endswith(".LICENSE") else path.suffix
    return FileResponse(path, media_type=MEDIA_TYPES[suffix], headers=REVALIDATE)
