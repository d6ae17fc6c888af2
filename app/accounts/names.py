"""How a page names a person, in the page's language (documents name them in English, the binding
text, with User.shown_as)."""

from __future__ import annotations

from app.accounts.models import User
from app.i18n.active import gettext


def person_on_page(user: User) -> str:
    """A person as a page names them, in the page's language: 'Amina Bello (badge 4471)' in English,
    as documents do (User.shown_as, which keeps the binding English)."""
    name = user.display_name
    if not name:
        unnamed = (
            gettext("administrator no. %(id)s (no name on record)")
            if user.role == "admin"
            else gettext("officer no. %(id)s (no name on record)")
        )
        name = unnamed % {"id": user.id}
    if user.badge_number:
        return gettext("%(name)s (badge %(badge)s)") % {"name": name, "badge": user.badge_number}
    return name
