"""The compiled catalogs (app/i18n/locale/LL/LC_MESSAGES/messages.mo), loaded once per locale."""

from __future__ import annotations

import gettext as stdlib_gettext
from functools import cache
from pathlib import Path

from app.i18n.locales import ENGLISH

LOCALE_DIR = Path(__file__).resolve().parent / "locale"
DOMAIN = "messages"


@cache
def translations(locale: str) -> stdlib_gettext.NullTranslations:
    """The locale's translations; English (and a locale without a catalog) is the identity."""
    if locale == ENGLISH:
        return stdlib_gettext.NullTranslations()
    # fallback=True: a missing catalog reads as English, never as an error page.
    return stdlib_gettext.translation(DOMAIN, LOCALE_DIR, languages=[locale], fallback=True)
