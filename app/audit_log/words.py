"""The audit page's words for what the log stores as codes ("station.key_rotated", "command_line"),
in the page's language. Only the page translates: the stored events, their hashes and the CSV keep
the codes exactly as recorded."""

from __future__ import annotations

from app.audit.recorder import ANONYMOUS
from app.i18n.active import gettext as _
from app.i18n.active import pgettext


def _record_kinds() -> dict[str, str]:
    # The part of an action before its dot, and an event's kind of record.
    return {
        "user": pgettext("audit log: kind of record", "user"),
        "station": pgettext("audit log: kind of record", "station"),
        "vehicle": pgettext("audit log: kind of record", "vehicle"),
        "signing_key": pgettext("audit log: kind of record", "signing key"),
        "certificate": pgettext("audit log: kind of record", "certificate"),
        "refusal": pgettext("audit log: kind of record", "refusal"),
        "type_assessment": pgettext("audit log: kind of record", "type assessment"),
        "service": pgettext("audit log: kind of record", "service"),
        "sign_in": pgettext("audit log: kind of record", "sign in"),
        "sign_out": pgettext("audit log: kind of record", "sign out"),
    }


def _happenings() -> dict[str, str]:
    # The part of an action after its dot: what happened to the record.
    return {
        "created": pgettext("audit log: what happened", "created"),
        "changed": pgettext("audit log: what happened", "changed"),
        "deleted": pgettext("audit log: what happened", "deleted"),
        "enabled": pgettext("audit log: what happened", "enabled"),
        "disabled": pgettext("audit log: what happened", "disabled"),
        "retired": pgettext("audit log: what happened", "retired"),
        "key_rotated": pgettext("audit log: what happened", "key rotated"),
        "password_changed": pgettext("audit log: what happened", "password changed"),
        "second_factor_enrolment_started": pgettext(
            "audit log: what happened", "second factor enrolment started"
        ),
        "second_factor_enrolled": pgettext("audit log: what happened", "second factor enrolled"),
        "second_factor_reset": pgettext("audit log: what happened", "second factor reset"),
        "recovery_code_used": pgettext("audit log: what happened", "recovery code used"),
        "reauthenticated": pgettext("audit log: what happened", "reauthenticated"),
        "reauthentication_failed": pgettext("audit log: what happened", "reauthentication failed"),
        "reauthentication_locked_out": pgettext("audit log: what happened", "reauthentication locked out"),
        "dynamics_recorded": pgettext("audit log: what happened", "dynamics recorded"),
        "issued": pgettext("audit log: what happened", "issued"),
        "revoked": pgettext("audit log: what happened", "revoked"),
        "started": pgettext("audit log: what happened", "started"),
        "success": pgettext("audit log: what happened", "success"),
        "bad_credentials": pgettext("audit log: what happened", "bad credentials"),
        "locked_out": pgettext("audit log: what happened", "locked out"),
    }


def _actor_kinds() -> dict[str, str]:
    return {
        "user": pgettext("audit log: kind of actor", "user"),
        "station": pgettext("audit log: kind of actor", "station"),
        "command_line": pgettext("audit log: kind of actor", "command line"),
        "anonymous": pgettext("audit log: kind of actor", "anonymous"),
    }


def _plain(code: str) -> str:
    """A code nobody has given words yet, as the page showed every code before: its underscores spaces."""
    return code.replace("_", " ")


def record_kind(code: str) -> str:
    """A kind of record ("signing_key") in the page's language, lower case."""
    return _record_kinds().get(code) or _plain(code)


def action_words(action: str) -> str:
    """An action ("station.key_rotated") in the page's language: "station: key rotated" in English."""
    kind, dot, happened = action.partition(".")
    if not dot:
        return record_kind(kind)
    what = _happenings().get(happened) or _plain(happened)
    # Translators: an audit log action, e.g. "station: key rotated": the kind of record, then what happened.
    return _("%(kind)s: %(event)s") % {"kind": record_kind(kind), "event": what}


def actor_kind(code: str) -> str:
    """A kind of actor ("command_line") in the page's language, lower case."""
    return _actor_kinds().get(code) or _plain(code)


def actor_label(kind: str, label: str) -> str:
    """Who acted, as the log names them; the anonymous actor's stored label in the page's language."""
    if kind == "anonymous" and label == ANONYMOUS.label:
        return pgettext("audit log: who", "not signed in")
    return label


def first_upper(words: str) -> str:
    """The words with a capital first letter and the rest as they are (a list's option)."""
    return words[:1].upper() + words[1:]
