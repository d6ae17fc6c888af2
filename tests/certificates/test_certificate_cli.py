"""`trikecert verify` checks a payload offline; revoke, reissue and key rotation from the command line.

Since issue 21 `trikecert verify` names the status as the JSON verification does and exits 0 only for
a certificate in force: a genuine refusal (the study's document) exits 3, where it exited 0 before."""

from __future__ import annotations

import getpass
import json
from collections.abc import Iterator
from datetime import datetime
from pathlib import Path
from typing import Any
from urllib.parse import quote

import pytest
from certificate_helpers import FRONT_HEAVY, FRONT_HEAVY_READINGS, certify, register, study_certificate, weigh
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey
from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session

from app import config
from app.certificates.actors import Actor
from app.certificates.models import CertificateAudit
from app.certificates.service import revoke_certificate
from app.cli import main
from app.trust.keys import kid_of, okp_key, private_pem
from app.trust.models import SigningKey
from app.web.formatting import long_date


def run(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def issued(api: TestClient) -> dict[str, Any]:
    return study_certificate(api)


def test_verify_accepts_the_qr_url_against_a_saved_key_file(
    issued: dict[str, Any], api: TestClient, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    keys = tmp_path / "keys.json"
    keys.write_text(api.get("/.well-known/trikecert-keys.json").text)
    code, out, _err = run(capsys, "verify", issued["qr_url"], "--keys", str(keys))
    assert code == 3  # genuine, but a refusal certifies nothing
    assert f"GENUINE: signed by key {issued['key_id']}" in out
    assert "\nstatus: refused (a refusal: the vehicle is NOT certified)\n" in out
    assert "offline check: a revocation or a replacement shows online only" in out
    assert "\nissuer: 127.0.0.1:8000\n" in out
    assert f"refusal {issued['number']} for BDG 252 QH" in out
    assert "\nThis vehicle must not carry passengers\n" in out
    issued_at, expires_at = (datetime.fromisoformat(issued[k]) for k in ("issued_at", "expires_at"))
    assert f"issued {long_date(issued_at)}. This refusal stands until {long_date(expires_at)}.\n" in out
    assert "valid" not in out.lower().replace("genuine", "")


def test_verify_refuses_a_flipped_character_an_unknown_key_and_a_swapped_number(
    issued: dict[str, Any], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    token: str = issued["qr_payload"]
    middle = len(token) // 2
    flipped = token[:middle] + ("X" if token[middle] != "X" else "Y") + token[middle + 1 :]
    code, _out, err = run(capsys, "verify", flipped)
    assert code == 1
    assert "NOT GENUINE" in err
    assert "bad_signature" in err or "malformed" in err

    stranger = okp_key(Ed25519PrivateKey.generate())
    other_keys = tmp_path / "other.json"
    other_keys.write_text(
        json.dumps({"keys": [{**stranger.as_dict(private=False), "kid": kid_of(stranger)}]})
    )
    code, _out, err = run(capsys, "verify", token, "--keys", str(other_keys))
    assert code == 1
    assert "unknown_key" in err

    other_number = issued["number"].replace("000001", "000002")
    swapped = f"{issued['verify_url'].replace(issued['number'], other_number)}?p={quote(token, safe='')}"
    code, _out, err = run(capsys, "verify", swapped)
    assert code == 1
    assert "tampered" in err


def test_revoke_certificate_records_the_os_user_and_the_verify_page_says_revoked_at_once(
    issued: dict[str, Any],
    api: TestClient,
    client: TestClient,
    session: Session,
    capsys: pytest.CaptureFixture[str],
) -> None:
    number = issued["number"]
    assert (
        '<h1 class="status__headline" id="headline">NOT CERTIFIED: refusal</h1>'
        in client.get(f"/verify/{number}").text
    )
    code, out, _err = run(capsys, "revoke-certificate", number, "--reason", "Scale found out of calibration")
    assert code == 0
    assert f"Refusal {number} revoked. Reason: Scale found out of calibration" in out
    page = client.get(f"/verify/{number}")
    assert page.status_code == 200
    revoked_at = datetime.fromisoformat(
        api.get(f"/api/v1/certificates/{number}").json()["revocation"]["revoked_at"]
    )
    assert f'id="headline">REVOKED on {long_date(revoked_at)}</h1>' in page.text
    assert "Scale found out of calibration" in page.text
    audit = session.scalars(select(CertificateAudit).order_by(CertificateAudit.id)).all()
    assert [(a.action, a.actor) for a in audit][-1] == ("revoke", f"cli:{getpass.getuser()}")
    code, _out, err = run(capsys, "revoke-certificate", number, "--reason", "again")
    assert code == 2
    assert f"refusal {number} is already revoked" in err
    code, _out, err = run(capsys, "revoke-certificate", number, "--reason", "   ")
    assert code == 2


def test_reissue_supersedes_and_keeps_the_expiry(
    issued: dict[str, Any], api: TestClient, capsys: pytest.CaptureFixture[str]
) -> None:
    code, out, _err = run(capsys, "reissue-certificate", issued["number"], "--reason", "paper copy lost")
    assert code == 0
    new_number = out.split()[2].rstrip(";")
    new = api.get(f"/api/v1/certificates/{new_number}").json()
    assert (new["supersedes"], new["expires_at"], new["inspection_id"]) == (
        issued["number"],
        issued["expires_at"],
        issued["inspection_id"],
    )
    assert api.get(f"/api/v1/certificates/{issued['number']}").json()["status"] == "superseded"


def test_rotating_the_key_keeps_old_certificates_verifiable(
    issued: dict[str, Any], api: TestClient, capsys: pytest.CaptureFixture[str]
) -> None:
    code, out, _err = run(capsys, "rotate-signing-key")
    assert code == 0
    register_again = api.post(
        "/api/v1/inspections",
        json={
            "registration_number": "BDG 252 QH",
            "readings": {"front_kg": 108, "left_rear_kg": 115, "right_rear_kg": 135, "overall_kg": 359},
        },
    )
    newer = api.post(f"/api/v1/inspections/{register_again.json()['id']}/certificate").json()
    assert newer["key_id"] != issued["key_id"]
    assert newer["key_id"] in out
    published = api.get("/.well-known/trikecert-keys.json").json()["keys"]
    assert [(k["kid"], k["active"]) for k in published] == [
        (newer["key_id"], True),
        (issued["key_id"], False),
    ]
    for body, status in ((issued, "superseded"), (newer, "refused")):
        code, out, _err = run(capsys, "verify", body["qr_url"])
        assert code == 3  # genuine under either key; neither paper certifies the vehicle
        assert f"\nstatus: {status} " in out


def test_signing_keys_saves_the_published_set(
    issued: dict[str, Any], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    target = tmp_path / "saved.json"
    assert run(capsys, "signing-keys", "--output", str(target))[0] == 0
    assert json.loads(target.read_text())["keys"][0]["kid"] == issued["key_id"]
    assert run(capsys, "verify", issued["qr_payload"], "--keys", str(target))[0] == 3  # a refusal


@pytest.fixture
def configured_key(monkeypatch: pytest.MonkeyPatch) -> Iterator[Ed25519PrivateKey]:
    private = Ed25519PrivateKey.generate()
    monkeypatch.setenv("TRIKECERT_SIGNING_KEY", private_pem(private))
    config.get_settings.cache_clear()
    yield private
    monkeypatch.delenv("TRIKECERT_SIGNING_KEY")
    config.get_settings.cache_clear()


def test_a_configured_key_signs_and_is_published_but_its_private_half_is_never_stored(
    configured_key: Ed25519PrivateKey, api: TestClient, session: Session, capsys: pytest.CaptureFixture[str]
) -> None:
    body = study_certificate(api)
    assert body["key_id"] == kid_of(okp_key(configured_key))
    row = session.scalars(select(SigningKey)).one()
    assert (row.kid, row.source) == (body["key_id"], "configuration")
    assert not any("private" in column.name for column in SigningKey.__table__.columns)
    code, _out, err = run(capsys, "rotate-signing-key")
    assert code == 2
    assert "TRIKECERT_SIGNING_KEY" in err


def test_verify_names_the_status_a_certificate_in_force_exits_0_and_a_revoked_one_3(
    api: TestClient, session: Session, capsys: pytest.CaptureFixture[str]
) -> None:
    register(api, FRONT_HEAVY)
    body = certify(api, weigh(api, "KTU-417-XA", FRONT_HEAVY_READINGS))
    code, out, _err = run(capsys, "verify", body["qr_url"])
    assert code == 0
    assert "\nstatus: certified (a certificate in force: the vehicle is certified as below)\n" in out
    assert "offline check" not in out  # this service's record was read
    revoke_certificate(session, number=body["number"], actor=Actor.of_cli(), reason="Wrong wheel readings")
    code, out, _err = run(capsys, "verify", body["qr_url"])
    assert code == 3
    assert "\nstatus: revoked (REVOKED: it certifies nothing)\n" in out
    assert ": Wrong wheel readings\n" in out
    assert out.splitlines()[-1].startswith("revoked on ")
