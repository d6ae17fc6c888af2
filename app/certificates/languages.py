"""The languages a paper is printed in: English, binding, and the officer's choice of a second one."""

from __future__ import annotations

from app.config import SECOND_LANGUAGES, Settings
from app.i18n.active import gettext as _
from app.i18n.locales import ENGLISH, ENGLISH_NAMES, NATIVE_NAMES


def language_name(locale: str) -> str:
    """A language as the officer's choice names it: its English name, and its own where they differ."""
    english, native = ENGLISH_NAMES[locale], NATIVE_NAMES[locale]
    return english if english == native else f"{english} ({native})"


def paper_language_choices(settings: Settings) -> list[tuple[str, str, bool]]:
    """The issue form's choices (value, words, chosen): English only, or English and one other."""
    default = settings.paper_second_language or ENGLISH
    choices = [(ENGLISH, _("English only"), default == ENGLISH)]
    for locale in SECOND_LANGUAGES:
        words = _("English and %(language)s") % {"language": language_name(locale)}
        choices.append((locale, words, default == locale))
    return choices
