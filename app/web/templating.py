"""The Jinja2 environment and render(): every page gets the signed-in user, CSRF token and flash."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import jinja2
from starlette.requests import Request
from starlette.responses import HTMLResponse
from starlette.templating import Jinja2Templates

from app.config import get_settings
from app.i18n import active as i18n
from app.web import formatting
from app.web.language import language_links
from app.wording import (
    case_name,
    chart_caption,
    layout_of,
    rear_weight_heading,
    variance_note,
    verdict_mark,
    wheel_rows,
)

TEMPLATES_DIR = Path(__file__).resolve().parents[2] / "templates"
# The service's name in the page header; "Keke" is what the vehicle is called in every language.
SERVICE_NAME = i18n.N_("Keke stability certification")


def service_name() -> str:
    """The service's name in the active language (the header, every page's title)."""
    return i18n.gettext(SERVICE_NAME)


_env = jinja2.Environment(
    loader=jinja2.FileSystemLoader(TEMPLATES_DIR),
    autoescape=True,
    undefined=jinja2.StrictUndefined,
    trim_blocks=True,
    lstrip_blocks=True,
    extensions=["jinja2.ext.i18n"],
)
# newstyle: {{ _("…", name=value) }} escapes and formats like every other expression.
_env.install_gettext_callables(  # type: ignore[attr-defined]
    i18n.gettext, i18n.ngettext, newstyle=True, pgettext=i18n.pgettext
)
_env.filters.update(
    kg=formatting.kg,
    ratio=formatting.ratio,
    spread_ratio=formatting.spread_ratio,
    signed=formatting.signed,
    local_time=formatting.local_time,
    load_kg=formatting.load_kg,
    long_date=formatting.long_date,
    unbroken=formatting.unbroken,
    plates_kept=formatting.plates_kept,
    or_not_recorded=formatting.or_not_recorded,
    layout_title=formatting.layout_title,
)
_env.globals.update(
    html_lang=i18n.html_lang,
    language_links=language_links,
    service_name=service_name,
    limit_text=formatting.limit_text,
    axles_of=formatting.axles_of,
    case_name=case_name,
    verdict_mark=verdict_mark,
    rear_weight_heading=rear_weight_heading,
    variance_note=variance_note,
    chart_caption=chart_caption,
    wheel_rows=wheel_rows,
    layout_of=layout_of,
    not_recorded=formatting.not_recorded,
)
templates = Jinja2Templates(env=_env)


def _unwired(_login: Any) -> bool:
    raise RuntimeError("app.web.templating: no navigation rule; the composition root sets one")


_navigation_rule: Callable[[Any], bool] = _unwired


def use_navigation_rule(rule: Callable[[Any], bool]) -> None:
    """Set which signed-in sessions the layout offers the navigation to (the accounts package knows
    whether a session has passed its second factor; the composition root passes its rule in)."""
    global _navigation_rule
    _navigation_rule = rule


def render(
    request: Request,
    name: str,
    context: dict[str, Any] | None = None,
    *,
    status_code: int = 200,
) -> HTMLResponse:
    """Render a page; the layout reads the signed-in session from request.state."""
    login = getattr(request.state, "login", None)
    page: dict[str, Any] = {
        "login": login,
        "user": login.user if login else None,
        # Before the second factor, the pages behind it are not offered (they would only send back).
        "navigation": login is not None and _navigation_rule(login),
        "csrf_token": login.csrf_token if login else "",
        "flash": getattr(request.state, "flash", None),
        "issuing_authority": get_settings().issuing_authority,
        "errors": {},
        "values": {},
    }
    page.update(context or {})
    return templates.TemplateResponse(request, name, page, status_code=status_code)
