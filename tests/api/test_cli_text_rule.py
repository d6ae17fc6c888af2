"""The `trikecert` command keeps the same text rule as the API and the pages: a refused character or
an over-long text is a clear error (exit 2, the field and what to do) and nothing is stored."""

from __future__ import annotations

import io
import unicodedata

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session
from study_data import STUDY_READINGS, STUDY_VEHICLE

from app.accounts.models import User
from app.certificates.models import CertificateRevocation
from app.cli import main
from app.stations.models import Station

PASSWORD = "correct horse battery"


def run(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str]:
    """Exit code and standard error of one command."""
    code = main(list(args))
    lines = capsys.readouterr().err.strip().splitlines()
    return code, lines[-1] if lines else ""  # the command's own last word (the app may log before it)


REFUSED = {
    "NUL": ("\x00", "U+0000"),
    "right-to-left override": ("\u202e", "U+202E"),
    "zero-width space": ("\u200b", "U+200B"),
    "next line (C1)": ("\x85", "U+0085"),
}


@pytest.mark.parametrize("bad", REFUSED)
def test_create_station_refuses_a_name_or_detail_with_a_refused_character(
    capsys: pytest.CaptureFixture[str], session: Session, bad: str
) -> None:
    char, words = REFUSED[bad]
    code, err = run(capsys, "create-station", f"Ag{char}bara")
    assert code == 2
    assert err.startswith("trikecert: name: remove")
    assert words in err
    code, err = run(capsys, "create-station", "Agbara", "--location", f"Lagos{char}")
    assert code == 2
    assert "location: remove" in err
    assert words in err
    assert session.scalars(select(Station)).all() == []


def test_create_station_refuses_a_name_too_long_instead_of_cutting_it(
    capsys: pytest.CaptureFixture[str], session: Session
) -> None:
    code, err = run(capsys, "create-station", "A" * 121)
    assert code == 2
    assert "name: give at most 120 characters, not 121" in err
    assert session.scalars(select(Station)).all() == []


def test_create_station_stores_a_decomposed_name_composed(
    capsys: pytest.CaptureFixture[str], session: Session
) -> None:
    code, _err = run(capsys, "create-station", unicodedata.normalize("NFD", "Ṣàngó weighbridge"))
    assert code == 0
    assert session.scalars(select(Station.name)).all() == ["Ṣàngó weighbridge"]


def test_update_station_refuses_a_new_name_with_a_refused_character(
    capsys: pytest.CaptureFixture[str], session: Session
) -> None:
    assert run(capsys, "create-station", "Agbara")[0] == 0
    code, err = run(capsys, "update-station", "Agbara", "--name", "Ag\u2066bara")
    assert code == 2
    assert "U+2066" in err
    session.expire_all()
    assert session.scalars(select(Station.name)).all() == ["Agbara"]


@pytest.mark.parametrize("bad", REFUSED)
def test_create_user_refuses_an_email_with_a_refused_character(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch, session: Session, bad: str
) -> None:
    char, words = REFUSED[bad]
    monkeypatch.setattr("sys.stdin", io.StringIO(PASSWORD + "\n"))
    code, err = run(capsys, "create-user", f"adm{char}in@example.org", "--role", "admin", "--name", "Ada Obi")
    assert code == 2
    assert err.startswith("trikecert: email: remove")
    assert words in err
    assert session.scalars(select(User)).all() == []


def test_create_user_refuses_a_password_with_a_control_character(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch, session: Session
) -> None:
    monkeypatch.setattr("sys.stdin", io.StringIO("correct\thorse battery\n"))
    code, err = run(capsys, "create-user", "admin@example.org", "--role", "admin", "--name", "Ada Obi")
    assert code == 2
    assert "password: remove the control character U+0009 (TAB)" in err
    assert session.scalars(select(User)).all() == []


@pytest.mark.parametrize("bad", REFUSED)
def test_revoke_refuses_a_reason_with_a_refused_character(
    capsys: pytest.CaptureFixture[str], api: TestClient, session: Session, bad: str
) -> None:
    char, words = REFUSED[bad]
    assert api.post("/api/v1/vehicles", json=STUDY_VEHICLE).status_code == 201
    weighed = api.post(
        "/api/v1/inspections", json={"registration_number": "BDG 252 QH", "readings": STUDY_READINGS}
    )
    issued = api.post(f"/api/v1/inspections/{weighed.json()['id']}/certificate")
    assert issued.status_code == 201, issued.text
    code, err = run(capsys, "revoke-certificate", issued.json()["number"], "--reason", f"Scale{char} faulty")
    assert code == 2
    assert err.startswith("trikecert: reason: remove")
    assert words in err
    assert session.scalars(select(CertificateRevocation)).all() == []
