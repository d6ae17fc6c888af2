"""The audit page names what happened and who did it in the reader's language, while the log keeps
its codes exactly as recorded (the chain, the CSV and the filters' values are untouched)."""

from __future__ import annotations

import html
import re
from pathlib import Path
from types import SimpleNamespace

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session

from app.accounts import throttle
from app.audit.models import AuditEvent
from app.audit.recorder import ANONYMOUS, NAMED_CHANGES, Actor, act_as, record_event
from app.audit_log import words
from app.audit_log.service import ACTOR_KINDS, verify_log
from app.audited import FOLLOWED
from app.i18n.active import use_locale

ROOT = Path(__file__).resolve().parents[2]
LANGUAGES = ["ha", "yo", "ig", "pcm"]
OUTCOMES = (throttle.SUCCESS, throttle.BAD_CREDENTIALS, throttle.LOCKED_OUT, throttle.DISABLED)

# (actor kind, label, action, record type, record id): one of each kind of actor and of word.
EVENTS = [
    ("user", "Ngozi.Eze@example.org", "vehicle.created", "vehicle", "BDG252QH"),
    ("user", "Ngozi.Eze@example.org", "user.second_factor_reset", "user", "4"),
    ("station", "Ọ̀yọ́ weighbridge", "certificate.issued", "certificate", "TRK-1"),
    ("command_line", "root@records", "certificate.revoked", "certificate", "TRK-1"),
    ("anonymous", ANONYMOUS.label, "sign_in.bad_credentials", "user", "7"),
    ("station", "Ikeja weighbridge", "station.key_rotated", "station", "3"),
    ("user", "Ngozi.Eze@example.org", "sign_out", "user", "4"),
    ("user", "Ngozi.Eze@example.org", "signing_key.retired", "signing_key", "k-2026"),
]
# What the English page shows for them, which no other language's page may show.
ENGLISH = [
    "vehicle: created",
    "user: second factor reset",
    "certificate: issued",
    "certificate: revoked",
    "sign in: bad credentials",
    "station: key rotated",
    "signing key: retired",
    "(command line)",
    "(anonymous)",
    "not signed in",
    "Command line",
    "Anonymous",
    "Any signing key action",
    "Signing key",
]
# The same in Hausa (docs/translations.md's glossary: tasha, takardar shaida, an soke).
HAUSA = [
    "abin hawa: an ƙirƙira",
    "mai amfani: an sake saita mataki na biyu",
    "takardar shaida: an bayar",
    "takardar shaida: an soke",
    "shiga: imel ko kalmar sirri ba daidai ba",
    "tasha: an canza maɓalli",
    "maɓallin sa hannu: an daina amfani da shi",
    "(layin umarni)",
    "(wanda ba a sani ba)",
    "bai shiga ba",
    "Layin umarni",
    "Wanda ba a sani ba",
    "Maɓallin sa hannu",
]
_TAG = re.compile(r"<[^>]+>")


def visible(page: str) -> str:
    """The text a reader sees, tags dropped and entities read, runs of spaces made one."""
    return " ".join(html.unescape(_TAG.sub(" ", page)).split())


@pytest.fixture
def recorded(admin_web: TestClient, session: Session) -> list[AuditEvent]:
    """The events above, recorded as the app records them, after the admin's own sign-in."""
    for kind, label, action, target_type, target_id in EVENTS:
        act_as(session, Actor(kind, None, label))
        record_event(session, action=action, target_type=target_type, target_id=target_id, details={})
        session.commit()
    session.expire_all()
    return list(session.scalars(select(AuditEvent).order_by(AuditEvent.id)))


def test_the_english_page_names_actions_and_actors_as_before(
    admin_web: TestClient, recorded: list[AuditEvent]
) -> None:
    text = visible(admin_web.get("/admin/audit").text)
    assert [words for words in ENGLISH if words not in text] == []
    assert "Ngozi.Eze@example.org (user) sign out" in text  # an action with no dot, as it is stored


@pytest.mark.parametrize("choose", ["cookie", "accept-language"])
def test_the_hausa_page_names_actions_and_actors_in_hausa_and_keeps_the_log_as_recorded(
    admin_web: TestClient, session: Session, recorded: list[AuditEvent], choose: str
) -> None:
    english_csv = admin_web.get("/admin/audit.csv").text
    if choose == "cookie":
        admin_web.cookies.set("trikecert_lang", "ha")
        page = admin_web.get("/admin/audit")
    else:
        page = admin_web.get("/admin/audit", headers={"Accept-Language": "ha-NG, en;q=0.5"})

    assert page.status_code == 200
    assert '<html lang="ha"' in page.text
    text = visible(page.text)
    assert [words for words in HAUSA if words not in text] == []
    assert [words for words in ENGLISH if words in text] == []
    assert "Kowane aiki na maɓallin sa hannu" in text
    assert "Ngozi.Eze@example.org (mai amfani) fita" in text
    # The codes stay the filters' values, and the labels the log's own are shown as recorded.
    assert '<option value="station.key_rotated">tasha: an canza maɓalli</option>' in page.text
    assert '<option value="command_line">Layin umarni</option>' in page.text
    assert "Ọ̀yọ́ weighbridge" in text
    assert "root@records" in text
    # Only the page translates: the stored events, their chain and the CSV are as recorded.
    session.expire_all()
    stored = list(session.scalars(select(AuditEvent).order_by(AuditEvent.id)))
    assert [(e.actor_label, e.actor_kind, e.action, e.hash) for e in stored] == [
        (e.actor_label, e.actor_kind, e.action, e.hash) for e in recorded
    ]
    assert verify_log(session).intact
    assert admin_web.get("/admin/audit.csv").text == english_csv


def _recordable_actions() -> set[str]:
    """Every action the recorder can write: each followed record's created, changed, deleted and
    named changes, each sign-in outcome, and each action the code names itself."""
    found = {"sign_out"}
    named = {*NAMED_CHANGES.values(), "enabled", "disabled", "changed", "created", "deleted"}
    named |= {"second_factor_enrolled", "second_factor_reset", "second_factor_enrolment_started"}
    for audited in FOLLOWED.values():
        found |= {f"{audited.target_type}.{name}" for name in named}
        if audited.created_action is not None:  # a paper's kind, a sign-in's outcome
            found |= {
                audited.created_action(SimpleNamespace(kind=kind, outcome=outcome))
                for kind in ("certificate", "refusal")
                for outcome in OUTCOMES
            }
    source = "\n".join(path.read_text(encoding="utf-8") for path in (ROOT / "app").rglob("*.py"))
    found |= set(re.findall(r'"((?:certificate|refusal|user|vehicle|service)\.[a-z_]+)"', source))
    return found - {"user.id", "vehicle.id", "certificate.id"}  # columns, not actions


def test_every_action_and_actor_the_log_can_hold_has_words_in_every_language() -> None:
    actions = _recordable_actions()
    assert {"refusal.issued", "vehicle.dynamics_recorded", "user.reauthentication_locked_out"} <= actions
    for language in LANGUAGES:
        with use_locale(language):
            untranslated = [
                action
                for action in sorted(actions)
                if words.action_words(action) == action.replace("_", " ").replace(".", ": ")
                and language != "pcm"
            ]
            kinds = {kind: words.actor_kind(kind) for kind in ACTOR_KINDS}
            who = words.actor_label("anonymous", ANONYMOUS.label)
        assert untranslated == [], language
        assert kinds["anonymous"] != "anonymous", language
        assert kinds["command_line"] != "command line" or language == "pcm", language  # kept, as "API" is
        assert who != ANONYMOUS.label, language
    with use_locale("pcm"):  # Pidgin keeps "station", "user"; every word still comes from the catalog
        assert words.action_words("sign_in.bad_credentials") == "sign in: wrong email or password"
        assert words.action_words("certificate.revoked") == "certificate: dem don cancel am"


def test_a_code_nobody_gave_words_is_shown_as_stored_with_spaces() -> None:
    with use_locale("ha"):
        assert words.action_words("signxin.probe") == "signxin: probe"
        assert words.actor_label("station", "not signed in") == "not signed in"  # a station's own name
