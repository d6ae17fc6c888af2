"""The trust bundle's HTTP answer: its body, gzipped when asked, or 304 when the checker holds it."""

from __future__ import annotations

from starlette.responses import Response

from app.certificates.trust_bundle import Built

MEDIA_TYPE = "application/jose"


def etag_matches(header: str | None, etag: str) -> bool:
    """If-None-Match compares weakly (RFC 9110, 13.1.2): '*' or any listed tag, W/ or not."""
    if header is None:
        return False
    tags = [tag.strip().removeprefix("W/") for tag in header.split(",")]
    return "*" in tags or etag in tags


def accepts_gzip(header: str) -> bool:
    """Whether Accept-Encoding takes gzip (or anything) with a quality above zero."""
    for part in header.lower().split(","):
        name, _, params = part.strip().partition(";")
        if name.strip() in ("gzip", "*"):
            q = params.strip().removeprefix("q=")
            return not params.strip().startswith("q=") or q.strip() not in ("0", "0.0", "0.00", "0.000")
    return False


def bundle_response(built: Built, accept_encoding: str, if_none_match: str | None) -> Response:
    """The bundle's answer to a request with these headers: 304 when If-None-Match names it."""
    zipped = accepts_gzip(accept_encoding)
    etag = built.gzip_etag if zipped else built.etag
    headers = {"ETag": etag, "Cache-Control": "no-cache", "Vary": "Accept-Encoding"}
    if etag_matches(if_none_match, etag):
        return Response(status_code=304, headers=headers)
    if zipped:
        headers["Content-Encoding"] = "gzip"
    return Response(built.gzipped if zipped else built.body, media_type=MEDIA_TYPE, headers=headers)
