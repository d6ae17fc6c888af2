"""The /check page's words as data: every one comes from the offline decision's one wording function
(app/trust/offline.py) or from app/wording.py, so that the JavaScript retypes none of them."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

from app.config import get_settings
from app.trust.offline import checked_against, words_table
from app.web.formatting import long_date, month_names, to_local
from app.wording import document_title, occupancy_sentence, status_headline_on

MAX_OCCUPANTS = 100  # a payload's occupancy is a whole number below 100 (app/trust/cwt.py)
DATE_SLOT = "{date}"


def _checked_prefix() -> str:
    """The words before the list's date in checked_against (its date and time are the device's to write)."""
    made_at = 0
    local = to_local(datetime.fromtimestamp(made_at, UTC))
    text = checked_against(made_at)
    return text[: text.index(long_date(local.date()))]


def checker_words() -> dict[str, Any]:
    """Everything the page says, by code: the offline words, occupancy, titles, dated headlines."""
    table = words_table()
    occupancy = table["occupancy"]
    # The table may stop short of the highest occupancy a payload can carry; the same function fills it.
    for name, compliant in (("certificate", True), ("refusal", False)):
        occupancy[name] = [occupancy_sentence(compliant, n) for n in range(MAX_OCCUPANTS)]
    return {
        **table,
        "dated": {
            code: status_headline_on("compliant", code, DATE_SLOT) for code in ("revoked", "superseded")
        },
        "titles": {"certificate": document_title("compliant"), "refusal": document_title("refusal")},
        "checked_against": {"prefix": _checked_prefix(), "time_zone": get_settings().display_timezone},
        # The months as the pages name them: a phone's Intl may not know the page's language.
        "months": month_names(),
    }
