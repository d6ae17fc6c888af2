"""Every field of every form of every page, found by opening each page of the app's route table (so a
new form or field is covered without a new test), is sent with each kind of character the text rule
refuses, and too long: the answer is a 4xx, the form comes back with the message beside the field, and
nothing is stored. The same form with good values is accepted, so each refusal is the field's own.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from functools import cache
from html.parser import HTMLParser
from itertools import count
from typing import Any
from urllib.parse import urlencode

import pyotp
import pytest
from fastapi.routing import iter_route_contexts
from fastapi.testclient import TestClient
from row_counts import rows_per_table
from sqlalchemy import CompoundSelect, Engine, String, Text, cast, select, union_all
from sqlalchemy.orm import Session
from text_classes import FOREIGN_DIGITS, INVISIBLE_CLASSES, named

from app.accounts.service import create_user
from app.config import get_settings
from app.db import Base
from app.main import create_app
from app.notifications.service import subscribe
from app.stations.models import Station
from app.vehicles.models import Vehicle
from web.webtools import ADMIN_EMAIL, PASSWORD, STUDY_READINGS, hidden, post_form, sign_in, weigh_study_fleet

# One character of each class the rule refuses (a surrogate cannot be written in UTF-8: its would-be
# bytes are sent, which the server reads as U+FFFD, and that is refused too), and text too long.
# tests/api/test_text_rule.py sends every character of each class to the same rule.
BAD = {
    "NUL": "\x00",
    "C1 next line": "\x85",
    "right-to-left override": "\u202e",
    "first strong isolate": "\u2068",
    "zero-width space": "\u200b",
    "surrogate bytes": "\ud800",
    "too long": "",
}
VISIBLE = {
    "text",
    "email",
    "password",
    "number",
    "search",
    "tel",
    "url",
    "date",
    "radio",
    "textarea",
    "select",
}
# Signing out is not a form with anything to refuse; the offline checker's text is read by the page's
# script on the phone and never sent (the server answers /check/ the same, whatever the query).
SKIPPED_ACTIONS = {"/logout", "/check/"}
SERIAL = count(1)
TYPE_PAGE = "/type-assessments/new?make=Bajaj&model=RE+4S"


@dataclass
class Field:
    """One input, select or text area as the page shows it."""

    name: str
    kind: str
    value: str
    input_id: str


@dataclass
class Form:
    """One form of a page."""

    page: str
    method: str
    action: str
    fields: list[Field] = field(default_factory=list)


class _Forms(HTMLParser):
    def __init__(self, page: str) -> None:
        super().__init__()
        self.page = page
        self.forms: list[Form] = []
        self._select: Field | None = None

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        found = {k: v or "" for k, v in attrs}
        if tag == "form":
            self.forms.append(
                Form(self.page, found.get("method", "get").lower(), found.get("action") or self.page)
            )
        elif tag in ("input", "textarea", "select") and found.get("name") and self.forms:
            kind = found.get("type", "text") if tag == "input" else tag
            if kind == "radio" and any(f.name == found["name"] for f in self.forms[-1].fields):
                return  # one field per radio group, identified by its first button
            if kind in ("submit", "button", "checkbox"):
                return
            entry = Field(found["name"], kind, found.get("value", ""), found.get("id", found["name"]))
            self.forms[-1].fields.append(entry)
            if tag == "select":
                self._select = entry
        elif tag == "option" and self._select is not None and ("selected" in found or not self._select.value):
            self._select.value = found.get("value", "")

    def handle_endtag(self, tag: str) -> None:
        if tag == "select":
            self._select = None


def forms_of(page: str, html: str) -> list[Form]:
    """Every form of a page that sends something a person types or chooses."""
    parser = _Forms(page)
    parser.feed(html)
    return [f for f in parser.forms if f.action not in SKIPPED_ACTIONS]


def good_values(form: Form, serial: int, site: Site) -> dict[str, str]:
    """Values the form accepts: what the page shows, and for the rest a good value by field name."""
    values = {f.name: f.value for f in form.fields}
    unique = {
        "registration_number": f"KTU {serial} XA" if form.action == "/vehicles/new" else "BDG 252 QH",
        "name": f"Agbara {serial} weighbridge",
        "email": f"officer{serial}@example.org" if form.action.startswith("/admin") else ADMIN_EMAIL,
    }
    known = {
        **STUDY_READINGS,
        "make": "Bajaj",
        "model": "RE",
        "wheelbase_m": "2.000",
        "driver_x_m": "0.930",
        "password": PASSWORD,
        "reason": "Scale found out of calibration",
        "role": "officer",
        "number": site.parameters["number"],
        "plate": "BDG 252 QH",
        **unique,
    }
    for name, value in known.items():
        if name in values and (not values[name] or name in unique):
            values[name] = value
    return values


def encoded(values: dict[str, str]) -> str:
    """The form as a browser would encode it; a surrogate goes as its would-be UTF-8 bytes."""
    return urlencode(values, encoding="utf-8", errors="surrogatepass")


def send(client: TestClient, form: Form, values: dict[str, str]) -> Any:
    """Submit the form with these values, by its method."""
    if form.method == "get":  # as a browser does: the query goes before the action's #fragment
        return client.get(f"{form.action.split('#')[0]}?{encoded(values)}", follow_redirects=False)
    headers = {"Content-Type": "application/x-www-form-urlencoded"}
    return client.post(form.action, content=encoded(values), headers=headers, follow_redirects=False)


# Counts of closed days, derived from the records and kept by whichever page reads them first
# (app/statistics/models.py): not input, so a refused request may fill them.
DERIVED = {name for name in Base.metadata.tables if name.startswith("statistics_")}


def snapshot(engine: Engine) -> tuple[dict[str, int], list[str]]:
    """Rows per table, and every text stored in any column (derived counts aside), in two statements
    (the test takes hundreds of snapshots)."""
    with engine.connect() as connection:
        texts = [text for text in connection.scalars(every_text_statement()) if text is not None]
    return rows_per_table(engine, leave_out=DERIVED), texts


@cache
def every_text_statement() -> CompoundSelect[Any]:
    """The statement reading every text stored in any column of the tables a snapshot reads."""
    return union_all(
        *(
            select(cast(column, Text))
            for table in Base.metadata.sorted_tables
            if table.name not in DERIVED
            for column in table.columns
            if isinstance(column.type, String | Text)
        )
    )


# ---- the pages, from the app's route table --------------------------------------------------------


@dataclass
class Site:
    """The signed-in administrator, a signed-out visitor, and the path parameter of every page."""

    admin: TestClient
    visitor: TestClient
    parameters: dict[str, str]


@pytest.fixture
def site(
    client: TestClient,
    session: Session,
    engine: Engine,
    study_vehicle: Vehicle,
    monkeypatch: pytest.MonkeyPatch,
) -> Iterator[Site]:
    """One of everything a page can show: the study's vehicle, an inspection, a certificate, a
    station, a second account and a request for reminders; the administrator signed in."""
    create_user(session, email=ADMIN_EMAIL, password=PASSWORD, role="admin")
    other = create_user(session, email="second@example.org", password=PASSWORD, role="officer")
    assert sign_in(client, ADMIN_EMAIL).status_code == 303
    page = "/vehicles/BDG252QH/inspections/new"
    done = post_form(client, page, page, dict(STUDY_READINGS))
    assert done.status_code == 303, done.text
    inspection_id = done.headers["location"].rsplit("/", 1)[-1]
    issued = post_form(client, done.headers["location"], f"/inspections/{inspection_id}/certificate", {})
    assert issued.status_code == 303, issued.text
    number = issued.headers["location"].rsplit("/", 1)[-1]
    station = post_form(client, "/admin/stations/new", "/admin/stations/new", {"name": "Ikeja weighbridge"})
    assert station.status_code == 200, station.text
    station_id = re.search(r'href="/admin/stations/(\d+)"', client.get("/admin/stations").text)
    assert station_id is not None
    weigh_study_fleet(session, model="RE 4S", suffix=" X")
    typed = post_form(client, TYPE_PAGE, "/type-assessments", {})
    assert typed.status_code == 303, typed.text
    # The walk sends /reminders once per bad text: the daily confirmation limits are not under test here.
    monkeypatch.setenv("TRIKECERT_CONFIRMATIONS_PER_CONTACT", "1000")
    monkeypatch.setenv("TRIKECERT_CONFIRMATIONS_PER_ADDRESS", "1000")
    get_settings.cache_clear()
    reminders = subscribe(
        session,
        vehicle=study_vehicle,
        channel="email",
        contact="owner@example.ng",
        client="testclient",
        settings=get_settings(),
    )
    session.commit()
    with TestClient(create_app(), raise_server_exceptions=False) as visitor:
        yield Site(
            client,
            visitor,
            {
                "registration_key": "BDG252QH",
                "inspection_id": inspection_id,
                "number": number,
                "station_id": station_id.group(1),
                "user_id": str(other.id),
                "type_assessment_id": typed.headers["location"].rsplit("/", 1)[-1],
                "locale": "en",  # the switcher link sets the language it names: the walk reads English
                "token": reminders.subscription.token,
            },
        )
    get_settings.cache_clear()


def page_paths(parameters: dict[str, str]) -> list[str]:
    """Every GET page of the officers' site, its path parameters filled in."""
    paths = []
    for route in iter_route_contexts(create_app().routes):
        if not route.path or route.path.startswith("/api/") or "GET" not in (route.methods or ()):
            continue
        path = route.path
        for name in re.findall(r"{(\w+)}", path):
            assert name in parameters, f"no value for {{{name}}} of {path}: add one to the site fixture"
            path = path.replace(f"{{{name}}}", parameters[name])
        paths.append(path)
    return paths


def all_forms(site: Site) -> list[tuple[TestClient, Form]]:
    """Every form on every page, with the client (signed in or not) that sees it."""
    found: list[tuple[TestClient, Form]] = []
    for path in page_paths(site.parameters):
        for client in (site.admin, site.visitor):
            page = client.get(path, follow_redirects=False)
            if page.status_code == 200 and page.headers["content-type"].startswith("text/html"):
                found += [(client, f) for f in forms_of(path, page.text) if (client, f.action) not in
                          {(c, g.action) for c, g in found}]  # fmt: skip
    return found


def fresh(client: TestClient, form: Form) -> Form:
    """The same form as the page shows it now (new one-time tokens)."""
    page = client.get(form.page)
    assert page.status_code == 200, f"{form.page} answers {page.status_code}"
    same = [f for f in forms_of(form.page, page.text) if f.action == form.action]
    assert same, f"{form.page} no longer shows the form to {form.action}"
    return same[0]


def with_current_code(client: TestClient, form: Form, values: dict[str, str]) -> dict[str, str]:
    """The enrolment form's code as the authenticator app would show it, from the secret on the page."""
    if form.action != "/account/two-factor":
        return values
    secret = re.search(r'<code id="secret" class="secret">([A-Z2-7]+)</code>', client.get(form.page).text)
    assert secret, "the enrolment page shows its secret"
    return {**values, "code": pyotp.TOTP(secret[1]).now()}


def bad_value(good: str, kind: str) -> str:
    """The good value with the refused character in it, or far too long."""
    if kind == "too long":
        return (good or "1") + "1" * 5000
    good = good or "1"
    return good[:1] + BAD[kind] + good[1:]


def expected_words(kind: str) -> str:
    """What the message beside the field must say."""
    if kind == "too long":
        return "characters, not"
    char = "\ufffd" if kind == "surrogate bytes" else BAD[kind]
    return f"U+{ord(char):04X}"


def test_every_visible_field_of_every_form_refuses_each_bad_text_beside_the_field(
    site: Site, engine: Engine
) -> None:
    forms = all_forms(site)
    actions = {form.action for _c, form in forms}
    # The walk found the forms a person fills in (a missing one here is a defect of the walk).
    assert {
        "/login",
        "/vehicles/new",
        "/admin/stations/new",
        "/admin/users/new",
        "/inspections",
        "/admin/audit",
    } <= actions
    walked = 0
    for client, found in forms:
        for entry in [f for f in found.fields if f.kind in VISIBLE]:
            form = fresh(client, found)  # a refused form leaves its one-time token unused
            # Taken once: each refusal below is asserted to leave the records as they were.
            before = snapshot(engine)
            for kind in BAD:
                values = good_values(form, next(SERIAL), site)
                values[entry.name] = bad_value(values.get(entry.name, ""), kind)
                response = send(client, form, values)
                where = f"{form.action} {entry.name} with {kind}"
                assert 400 <= response.status_code < 500, f"{where}: {response.status_code}"
                after = snapshot(engine)
                assert after[0] == before[0], f"{where}: a row was stored"
                assert sorted(after[1]) == sorted(before[1]), f"{where}: a text was changed"
                if form.action != "/verify":  # the public check says only that no such certificate exists
                    message = re.search(
                        rf'id="{re.escape(entry.input_id)}-error"[^>]*>(.*?)</p>', response.text, re.S
                    )
                    assert message is not None, f"{where}: no message beside the field"
                    assert expected_words(kind) in message.group(1), f"{where}: {message.group(1)}"
                walked += 1
            form = fresh(client, found)
            control = send(
                client, form, with_current_code(client, form, good_values(form, next(SERIAL), site))
            )
            assert control.status_code < 400, (
                f"{form.action} {entry.name}: good values refused: {control.text}"
            )
            if client is site.visitor:  # signed in by the sign-in form: a visitor again
                client.cookies.clear()
    assert walked > 100


def test_a_bad_character_in_a_hidden_field_is_never_stored_and_never_a_500(
    site: Site, engine: Engine
) -> None:
    """Tokens and the page to go on to are the service's own: tampered with, they are refused or
    ignored, never stored and never a server error."""
    tried = 0
    for client, found in all_forms(site):
        for entry in [f for f in found.fields if f.kind == "hidden"]:
            for kind in ("NUL", "right-to-left override", "surrogate bytes"):
                form = fresh(client, found)
                values = good_values(form, next(SERIAL), site)
                values[entry.name] = bad_value(values.get(entry.name, ""), kind)
                _counts, before = snapshot(engine)
                response = send(client, form, values)
                assert response.status_code < 500, f"{form.action} {entry.name}: {response.status_code}"
                _counts, after = snapshot(engine)
                char = "\ufffd" if kind == "surrogate bytes" else BAD[kind]
                assert not [t for t in after if char in t and t not in before], f"{form.action} {entry.name}"
                tried += 1
                if client is site.visitor:  # a sign-in that went through: a visitor again
                    client.cookies.clear()
    assert tried > 10


def test_a_name_typed_with_combining_accents_is_stored_composed(
    admin_web: TestClient, session: Session
) -> None:
    decomposed = "S\u0323a\u0300ngo\u0301 weighbridge"
    response = post_form(admin_web, "/admin/stations/new", "/admin/stations/new", {"name": decomposed})
    assert response.status_code == 200, response.text
    assert "Ṣàngó weighbridge" in admin_web.get("/admin/stations").text
    assert session.scalars(select(Station.name)).all() == ["Ṣàngó weighbridge"]


@pytest.mark.parametrize(
    "path",
    [
        "/vehicles/BDG%00252",
        "/vehicles/BDG%E2%80%AE252",
        "/vehicles/BDG%00252/inspections/new",
        "/vehicles/find?registration_number=BDG%00252",
        "/inspections?registration=BDG%00252",
        "/statistics?from=2026-01-01%00",
        "/verify?number=TRK%00",
    ],
)
def test_a_refused_character_in_a_page_address_is_a_4xx(web: TestClient, engine: Engine, path: str) -> None:
    """The probes that answered 500 on PostgreSQL: each is a 404 or the page again with its message."""
    before = snapshot(engine)
    response = web.get(path, follow_redirects=False)
    assert response.status_code in (404, 422), response.text
    assert "\x00" not in response.text
    assert snapshot(engine) == before


def test_signing_in_with_a_nul_in_the_email_is_refused_beside_the_field(
    client: TestClient, engine: Engine
) -> None:
    page = client.get("/login")
    values = {"email": "adm\x00in@example.org", "password": PASSWORD, "csrf_token": hidden(page.text)}
    before = snapshot(engine)
    response = client.post("/login", data=values, follow_redirects=False)
    assert response.status_code == 422, response.text
    assert "U+0000" in response.text
    assert 'id="email-error"' in response.text
    assert snapshot(engine) == before  # not even a failed attempt is logged


# ---- every class of issue 27 item 5, on one form of each kind -------------------------------------

CLASS_FIELDS = [
    ("/vehicles/new", "make"),
    ("/vehicles/new", "registration_number"),
    ("/admin/stations/new", "name"),
]
VEHICLE = {
    "registration_number": "KTU 77 XA",
    "make": "Bajaj",
    "model": "RE",
    "wheelbase_m": "2.000",
    "driver_x_m": "0.930",
}


@pytest.mark.parametrize(("action", "name"), CLASS_FIELDS)
def test_every_invisible_class_is_refused_beside_the_field_naming_the_character(
    admin_web: TestClient, engine: Engine, action: str, name: str
) -> None:
    good = VEHICLE if action == "/vehicles/new" else {"name": "Agbara weighbridge"}
    before = snapshot(engine)
    for kind, (char, _rule) in INVISIBLE_CLASSES.items():
        value = good[name][:3] + char + good[name][3:]
        response = post_form(admin_web, action, action, {**good, name: value})
        assert response.status_code == 422, f"{kind}: {response.status_code}"
        message = re.search(rf'id="{name}-error"[^>]*>(.*?)</p>', response.text, re.S)
        assert message is not None, f"{kind}: no message beside the field"
        assert named(char) in message.group(1), f"{kind}: {message.group(1)}"
        assert snapshot(engine) == before, f"{kind}: something was stored"


@pytest.mark.parametrize("digits", FOREIGN_DIGITS)
def test_numbers_are_read_only_in_the_digits_0_to_9_on_the_forms(
    web: TestClient, engine: Engine, study_vehicle: Vehicle, digits: str
) -> None:
    """٢٠١٢ or ２０１２ is refused beside its field, as the API refuses it, never read as 2012."""
    foreign = FOREIGN_DIGITS[digits]
    two, zero, one = foreign[0], foreign[1], foreign[2]
    vehicle = {
        **VEHICLE,
        "model_year": foreign,
        "wheelbase_m": f"{two}.{zero}{zero}{zero}",
        "driver_x_m": f"{zero}.9{one}",
    }
    inspection = {**STUDY_READINGS, "front_kg_1": f"{one}{zero}8"}
    before = snapshot(engine)
    forms = [
        ("/vehicles/new", vehicle, ["model_year", "wheelbase_m", "driver_x_m"]),
        ("/vehicles/BDG252QH/inspections/new", inspection, ["front_kg_1"]),
    ]
    for page, values, refused in forms:
        response = post_form(web, page, page, values)
        assert response.status_code == 422, f"{page}: {response.status_code}"
        for name in refused:
            message = re.search(rf'id="{name}-error"[^>]*>(.*?)</p>', response.text, re.S)
            assert message is not None, f"{page} {name}: no message beside the field"
            assert "number" in message.group(1) or "digits" in message.group(1), message.group(1)
    assert snapshot(engine) == before
