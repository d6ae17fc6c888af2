"""The language a request (or a PDF's second column) is being answered in, and gettext over it.

A ContextVar, set per request by the language middleware and per paper by use_locale(): the wording
functions call gettext() and so speak whatever language is active, from one function per fact.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar

from app.i18n.catalogs import translations
from app.i18n.locales import ENGLISH, HTML_LANG

_active: ContextVar[str] = ContextVar("trikecert_locale", default=ENGLISH)


def current_locale() -> str:
    """The active locale ('en', 'ha', 'yo', 'ig' or 'pcm')."""
    return _active.get()


def html_lang() -> str:
    """The BCP 47 tag of the active locale, for <html lang> ('en-GB', 'ha', 'yo', 'ig', 'pcm')."""
    return HTML_LANG[_active.get()]


@contextmanager
def use_locale(locale: str) -> Iterator[None]:
    """Speak the locale inside the block (a PDF's second language, a reply in the asker's)."""
    token = _active.set(locale)
    try:
        yield
    finally:
        _active.reset(token)


def set_locale(locale: str) -> None:
    """Make the locale active for the rest of this context (the request's middleware)."""
    _active.set(locale)


def gettext(message: str) -> str:
    """The message in the active language (its English text where no translation exists)."""
    return translations(_active.get()).gettext(message)


def ngettext(singular: str, plural: str, count: int) -> str:
    """The singular or plural form for the count, by the active language's plural rule."""
    return translations(_active.get()).ngettext(singular, plural, count)


def pgettext(context: str, message: str) -> str:
    """The message in its context (one English word, two meanings), in the active language."""
    return translations(_active.get()).pgettext(context, message)


def N_(message: str) -> str:  # noqa: N802 -- the name gettext tools know
    """Mark a message for extraction where it is defined; it is translated (gettext) where it is used."""
    return message


_ = gettext
