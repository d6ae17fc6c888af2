"""A feature phone chooses its language (USSD 4, SMS LANG) and is answered in it, every reply within one
SMS or one USSD screen; the /reminders pages and a subscription's emails speak the subscriber's."""

from __future__ import annotations

import re
from datetime import timedelta

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session

from app import config
from app.certificates.models import Certificate
from app.db import utcnow
from app.i18n.active import gettext, use_locale
from app.i18n.locales import HTML_LANG, LOCALES
from app.notifications.models import OutboxMessage, PhoneLanguage, Subscription
from app.notifications.service import plan_reminders
from app.notifications.sms_text import USSD_SCREEN, fits_sms, is_gsm7, sms_units
from notifications.phone_helpers import PHONE, State, certify, weigh
from notifications.test_gateway_check import replies, sms, ussd

pytestmark = pytest.mark.usefixtures("gateway_on")

HAUSA_CHOSEN = "Yanzu za a rika amsa wannan waya da Hausa."  # riƙa, as Hausa is texted
YORUBA_CHOSEN = "Lati isinsinyi, a o maa fesi si foonu yii ni Yoruba."  # Yorùbá without marks in SMS


def test_a_ussd_session_choosing_hausa_then_checking_a_plate_is_answered_in_hausa(
    client: TestClient, session: Session, states: list[State]
) -> None:
    choices = ussd(client, "4", "ATUid_lang")
    assert choices == "CON 1. English\n2. Hausa\n3. Yoruba\n4. Igbo\n5. Pidgin"
    chosen = ussd(client, "4*2", "ATUid_lang")
    assert chosen.startswith(f"END {HAUSA_CHOSEN}")
    menu = ussd(client, "", "ATUid_check")
    assert menu == (
        "CON Binciken keke\n1. Duba keke\n2. Tunatar da ni kafin ta kare\n3. Dakatar da tunatarwa\n"
        "4. Language/Harshe/Ede/Asusu"
    )
    assert ussd(client, "1", "ATUid_check") == "CON Shigar da lambar mota ko lambar takardar shaida"
    answer = ussd(client, "1*OYO 400 NN", "ATUid_check")
    assert answer.startswith("END OYO 400 NN: BA SHI DA TAKARDAR SHAIDA."), answer
    unknown = ussd(client, "1*ZZZ 999 ZZ", "ATUid_unknown")
    assert unknown == "END Babu keke ZZZ 999 ZZ a rajista: duba lambar mota ka sake aikawa."
    # Choosing English again gives the English screens back, as they always were.
    assert ussd(client, "4*1", "ATUid_english").startswith(
        "END Replies to this phone will now be in English."
    )
    assert ussd(client, "", "ATUid_again").startswith("CON Keke check\n1. Check a keke")


def test_sms_lang_yo_then_check_answers_in_yoruba_and_is_remembered_by_digest_only(
    client: TestClient, session: Session, states: list[State]
) -> None:
    assert sms(client, "LANG YO", "ATXid_lang") == 200
    assert replies(session)[-1].startswith(YORUBA_CHOSEN)
    assert sms(client, "CHECK OYO 400 NN", "ATXid_check") == 200
    reply = replies(session)[-1]
    assert reply.startswith("OYO 400 NN: KO NI IWE-ERI."), reply
    assert is_gsm7(reply)
    assert fits_sms(reply)
    assert sms(client, "zzz 999 zz", "ATXid_unknown") == 200
    assert replies(session)[-1] == "Ko si keke ZZZ 999 ZZ ninu akosile: sayewo nomba oko ki o tun fi ranse."
    kept = session.scalars(select(PhoneLanguage)).all()
    assert [row.language for row in kept] == ["yo"]
    assert PHONE.lstrip("+") not in kept[0].phone_digest
    assert "8012345667" not in kept[0].phone_digest
    # The other words that name a language: HAUSA alone, and LANG with a language's English name.
    assert sms(client, "hausa", "ATXid_hausa") == 200
    assert replies(session)[-1].startswith(HAUSA_CHOSEN)
    assert sms(client, "LANG english", "ATXid_english") == 200
    assert replies(session)[-1].startswith("Replies to this phone will now be in English.")
    assert sms(client, "CHECK ZZZ 999 ZZ", "ATXid_english_check") == 200
    assert replies(session)[-1] == "No keke ZZZ 999 ZZ is registered: check the plate and send it again."


@pytest.mark.parametrize("text", ["LANG FR", "LANG", "LANG HAUSA PLEASE", "LANG " + "x" * 300])
def test_a_bad_lang_value_gets_a_reply_listing_the_choices(
    client: TestClient, session: Session, text: str
) -> None:
    assert sms(client, text, "ATXid_bad") == 200
    assert replies(session) == [
        "Unknown language. Send LANG and one of: ENGLISH, HAUSA, YORUBA, IGBO, PIDGIN."
    ]
    assert session.scalars(select(PhoneLanguage)).all() == []


def test_every_reply_in_every_language_fits_one_sms_and_one_ussd_screen(
    client: TestClient, session: Session, states: list[State]
) -> None:
    others = ["LANG FR", "REMIND ZZZ 999 ZZ", "REMIND TRK-1", "123456", "CHECK", "hello"]
    for index, locale in enumerate(LOCALES):
        phone = f"+23480123456{index:02d}"  # a phone per language: each has its own check limit
        assert sms(client, f"LANG {locale}", f"ATXid_{locale}", phone) == 200
        assert ussd(client, f"4*{index + 1}", f"ATUid_{locale}", phone).startswith("END ")
        screens = [
            ussd(client, "", f"ATUid_{locale}_menu", phone),
            ussd(client, "4", f"ATUid_{locale}_4", phone),
        ]
        for number, state in enumerate(states):
            screens.append(ussd(client, f"1*{state.query}", f"ATUid_{locale}_{number}", phone))
            assert sms(client, f"CHECK {state.query}", f"ATXid_{locale}_{number}", phone) == 200
        for number, text in enumerate(others):
            assert sms(client, text, f"ATXid_{locale}_other_{number}", phone) == 200
        for text in ["1", "2", "2*ZZZ 999 ZZ", "9"]:
            screens.append(ussd(client, text, f"ATUid_{locale}_{text}", phone))
        assert all(len(screen) <= USSD_SCREEN for screen in screens)
        session.expire_all()
        bodies = session.scalars(
            select(OutboxMessage.body).where(OutboxMessage.recipient_masked.endswith(f"{index:02d}"))
        ).all()
        assert len(bodies) == 1 + len(states) + len(others), locale
        for body in bodies:
            assert fits_sms(body), (locale, body, sms_units(body))
            assert "..." not in body, (locale, body)  # shortened by choice, never cut
            assert locale == "en" or is_gsm7(body), (locale, body)  # phone spelling: 160, not 70
        # STOP last: it deletes the phone's unsent messages, then answers.
        assert sms(client, "STOP", f"ATXid_{locale}_stop", phone) == 200
        session.expire_all()
        stopped = session.scalars(
            select(OutboxMessage.body).where(OutboxMessage.recipient_masked.endswith(f"{index:02d}"))
        ).one()
        # The masked number's • needs Unicode (70), so this one is cut to fit, as in English.
        assert fits_sms(stopped), (locale, stopped)
        assert "..." not in ussd(client, "3", f"ATUid_{locale}_stop", phone)  # USSD 3: STOP's words


@pytest.mark.parametrize("locale", LOCALES)
def test_the_reminders_page_speaks_the_cookies_language(client: TestClient, locale: str) -> None:
    client.cookies.set("trikecert_lang", locale)
    page = client.get("/reminders")
    assert page.status_code == 200
    assert f'<html lang="{HTML_LANG[locale]}"' in page.text
    with use_locale(locale):
        heading, label, button = (
            gettext("Get reminders before a certificate expires"),
            gettext("Email address"),
            gettext("Send the link"),
        )
    assert f"<h1>{heading}</h1>" in page.text
    assert label in page.text
    assert button in page.text
    if locale != "en":
        assert "Get reminders before a certificate expires" not in page.text
        assert "Send the link" not in page.text


def test_a_subscription_made_in_hausa_gets_its_confirmation_email_in_hausa(
    api: TestClient, client: TestClient, session: Session
) -> None:
    certify(api, weigh(api, "KTU 417 XA"))
    client.cookies.set("trikecert_lang", "ha")
    form = client.get("/reminders")
    token = re.search(r'name="csrf_token" value="([^"]+)"', form.text)
    assert token is not None
    done = client.post(
        "/reminders", data={"csrf_token": token[1], "plate": "ktu 417 xa", "email": "a@example.ng"}
    )
    assert done.status_code == 200
    assert "Mun aika hanyar haɗi zuwa" in done.text
    assert '<html lang="ha"' in done.text
    subscription = session.scalars(select(Subscription)).one()
    assert subscription.language == "ha"
    message = session.scalars(select(OutboxMessage).where(OutboxMessage.purpose == "confirm")).one()
    assert message.subject == "Tabbatar da tunatarwa game da KTU 417 XA"
    assert "Don tabbatarwa, buɗe wannan hanyar haɗin:" in message.body  # the page's letters, not SMS's
    assert f"/reminders/confirm/{subscription.token}" in message.body
    # A bad input's message in Hausa too.
    refused = client.post("/reminders", data={"csrf_token": token[1], "plate": "", "email": "a@example.ng"})
    assert refused.status_code == 422
    assert "Shigar da lambar mota, kamar BDG 252 QH" in refused.text


def test_reminders_speak_the_phones_choice_and_the_language_an_email_subscribed_in(
    api: TestClient, client: TestClient, session: Session
) -> None:
    number = certify(api, weigh(api, "KTU 417 XA"))
    assert sms(client, "LANG HA", "ATXid_ha") == 200
    assert sms(client, "REMIND KTU 417 XA", "ATXid_remind") == 200
    client.cookies.set("trikecert_lang", "yo")
    form = client.get("/reminders")
    token = re.search(r'name="csrf_token" value="([^"]+)"', form.text)
    assert token is not None
    data = {"csrf_token": token[1], "plate": "KTU 417 XA", "email": "a@example.ng"}
    assert client.post("/reminders", data=data).status_code == 200
    session.expire_all()
    confirm_sms = session.scalars(
        select(OutboxMessage.body).where(OutboxMessage.purpose == "confirm", OutboxMessage.channel == "sms")
    ).one()
    assert confirm_sms.startswith("Lambar trikecert ")
    assert is_gsm7(confirm_sms)
    for subscription in session.scalars(select(Subscription)):
        subscription.confirmed_at = utcnow()
    session.commit()
    expires = session.scalars(select(Certificate.expires_at).where(Certificate.number == number)).one()
    assert plan_reminders(session, config.get_settings(), now=expires - timedelta(days=20)) == 2
    by_channel = {
        row.channel: row
        for row in session.scalars(select(OutboxMessage).where(OutboxMessage.purpose == "reminder_30"))
    }
    assert "za ta kare nan da kwana 30" in by_channel["sms"].body  # Hausa, as texted
    assert by_channel["sms"].body.endswith("Amsa STOP don dakatarwa.")
    assert fits_sms(by_channel["sms"].body)
    email = by_channel["email"]
    assert email.subject is not None
    assert "yóò parí ní ọjọ́ 30 sí i" in email.subject  # Yoruba, with its marks
    assert "Láti dá àwọn ìránlétí wọ̀nyí dúró, ṣí líǹkì yìí:" in email.body
    assert email.unsubscribe_url is not None
