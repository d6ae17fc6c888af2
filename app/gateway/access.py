"""Who may call the gateway's callbacks: the secret token in the URL, and the configured addresses.
The gateway signs nothing, so anything else is answered 404 (as if there were no such address) and
counted in /metrics."""

from __future__ import annotations

import hmac
import ipaddress

from fastapi import HTTPException
from prometheus_client import Counter
from starlette.requests import Request

from app.config import get_settings

REFUSED = Counter(
    "trikecert_gateway_callbacks_refused_total",
    "Gateway callbacks answered 404: no callbacks configured, a wrong token, or an address not allowed",
    ["reason"],
)


def _allowed_address(address: str, allowed: str) -> bool:
    if not allowed:
        return True
    try:
        ip = ipaddress.ip_address(address)
    except ValueError:
        return False
    return any(ip in ipaddress.ip_network(entry, strict=False) for entry in allowed.split(","))


def callback_allowed(request: Request) -> None:
    """A dependency: 404 unless callbacks are on, the token matches and the address is allowed."""
    settings = get_settings()
    expected = settings.gateway_callback_token
    if expected is None:
        REFUSED.labels("off").inc()
        raise HTTPException(404)
    given = request.query_params.get("token", "")
    if not hmac.compare_digest(given.encode(), expected.get_secret_value().encode()):
        REFUSED.labels("token").inc()
        raise HTTPException(404)
    if not _allowed_address(request.client.host if request.client else "", settings.gateway_allowed_ips):
        REFUSED.labels("address").inc()
        raise HTTPException(404)
