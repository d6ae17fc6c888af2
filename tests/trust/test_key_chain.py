"""A signing key counts only when it chains to the key the store holds (issue 27): a key row the app's
own role inserted, and the certificates signed with it, are NOT genuine online and absent from the
published keys and the trust bundle; a rotation keeps the old papers genuine and hands the bundle's
trust to the new key; the keys on record at the migration are vouched for once; a withdrawn key's
papers stop counting online and show "Cannot confirm" offline."""

from __future__ import annotations

import json
import time
from datetime import UTC, datetime
from typing import Any
from urllib.parse import quote

import pytest
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey
from fastapi.testclient import TestClient
from offline_cases import COMPLIANT, COMPLIANT_READINGS, _issue, trust_anchor
from sqlalchemy import Engine, insert, select, text
from sqlalchemy.orm import Session

from app.certificates import service
from app.certificates.trust_bundle import forget_bundles
from app.cli import main
from app.trust.bundle import BundleRefused, open_bundle, unpack_bundle
from app.trust.keys import trusted_key_rows
from app.trust.models import KeyEndorsement, KeyGrandfathered, SigningKey
from app.trust.offline import decide
from app.trust.signer import MemorySigner
from app.wording import QR_NOT_GENUINE

BUNDLE = "/.well-known/trikecert-trust"
KEYS = "/.well-known/trikecert-keys.json"


def _rogue_row(engine: Engine, rogue: MemorySigner) -> None:
    """What the insider did first: a signing_key row of their own, inserted with the app's role."""
    with engine.begin() as connection:
        connection.execute(
            insert(SigningKey.__table__),  # type: ignore[arg-type]
            {
                "kid": rogue.kid,
                "public_jwk": rogue.public_jwk(),
                "source": "file",
                "active": True,
                "created_at": datetime.now(UTC),
            },
        )


def _verify_json(client: TestClient, paper: dict[str, Any]) -> dict[str, Any]:
    answer = client.get(f"/api/v1/verify/{paper['number']}?p={quote(paper['qr_payload'], safe='')}")
    assert answer.status_code == 200, answer.text
    body: dict[str, Any] = answer.json()
    return body


def test_a_key_row_the_app_role_inserted_signs_nothing_genuine(
    api: TestClient, engine: Engine, monkeypatch: pytest.MonkeyPatch
) -> None:
    genuine = _issue(api, "KTU 417 XA", COMPLIANT, COMPLIANT_READINGS)
    rogue = MemorySigner(Ed25519PrivateKey.generate(), "file")
    _rogue_row(engine, rogue)
    # Then a certificate row signed with that key, written as the app's own role writes one (with its
    # audit event, so that the records' own triggers let it in): the insider holds the role, not the key.
    monkeypatch.setattr(service, "current_signer", lambda _session, _settings: rogue)
    forged = _issue(api, "KTU 418 XA", COMPLIANT, COMPLIANT_READINGS)
    monkeypatch.undo()
    assert forged["key_id"] == rogue.kid

    body = _verify_json(api, forged)
    assert (body["qr"], body["qr_reason"]) == ("not_genuine", "unknown_key")
    page = api.get(f"/verify/{forged['number']}?p={quote(forged['qr_payload'], safe='')}")
    assert QR_NOT_GENUINE in page.text
    assert 'data-genuine="false"' in page.text
    assert _verify_json(api, genuine)["qr"] == "genuine"

    published = [key["kid"] for key in api.get(KEYS).json()["keys"]]
    assert published == [genuine["key_id"]]
    bundle = unpack_bundle(api.get(BUNDLE).text).bundle
    assert [key.kid for key in bundle.keys] == [genuine["key_id"]]
    assert decide(forged["qr_url"], bundle, int(time.time())).code == "unknown_key"
    assert decide(genuine["qr_url"], bundle, int(time.time())).code == "certified"


def test_a_statement_the_insider_signed_with_their_own_key_vouches_for_nothing(
    api: TestClient, engine: Engine, session: Session
) -> None:
    genuine = _issue(api, "KTU 417 XA", COMPLIANT, COMPLIANT_READINGS)
    rogue = MemorySigner(Ed25519PrivateKey.generate(), "file")
    _rogue_row(engine, rogue)
    from app.trust.bundle import b64url, endorsement_text

    with engine.begin() as connection:
        for relation, signer, subject, subject_x in (
            ("successor", rogue.kid, genuine["key_id"], trust_anchor().public_jwk()["x"]),
            ("predecessor", rogue.kid, genuine["key_id"], trust_anchor().public_jwk()["x"]),
        ):
            at = int(time.time())
            signature = rogue.sign(endorsement_text(relation, signer, subject, subject_x, at))  # type: ignore[arg-type]
            connection.execute(
                insert(KeyEndorsement.__table__),  # type: ignore[arg-type]
                {
                    "signer_kid": signer,
                    "subject_kid": subject,
                    "relation": relation,
                    "at": at,
                    "signature": b64url(signature),
                    "created_at": datetime.now(UTC),
                },
            )
    assert [row.kid for row in trusted_key_rows(session).rows] == [genuine["key_id"]]


def test_rotation_keeps_old_papers_genuine_and_hands_the_bundle_over(
    api: TestClient, session: Session, capsys: pytest.CaptureFixture[str]
) -> None:
    old = _issue(api, "KTU 417 XA", COMPLIANT, COMPLIANT_READINGS)
    before = api.get(BUNDLE).text
    pinned = unpack_bundle(before).bundle.keys[0]
    assert main(["rotate-signing-key"]) == 0
    capsys.readouterr()
    new = _issue(api, "KTU 418 XA", COMPLIANT, COMPLIANT_READINGS)
    assert new["key_id"] != old["key_id"]
    assert _verify_json(api, old)["qr"] == "genuine"
    assert _verify_json(api, new)["qr"] == "genuine"

    after = api.get(BUNDLE).text
    opened = open_bundle(
        after, trusted={pinned.kid: pinned.x}, held=unpack_bundle(before).bundle
    )  # a checker pinned to the old key follows the handover
    assert opened.kid == new["key_id"]
    keys = {key.kid: key for key in opened.bundle.keys}
    assert keys[old["key_id"]].status == "retired"
    assert [(e.relation, e.by) for e in keys[new["key_id"]].endorsements] == [("successor", old["key_id"])]
    assert [(e.relation, e.by) for e in keys[old["key_id"]].endorsements] == [("predecessor", new["key_id"])]
    now = int(time.time())
    assert decide(old["qr_url"], opened.bundle, now).code == "certified"
    assert decide(new["qr_url"], opened.bundle, now).code == "certified"

    # A bundle signed by a key no trusted key handed over to is refused, and keeps nothing.
    stranger = MemorySigner(Ed25519PrivateKey.generate(), "file")
    with pytest.raises(BundleRefused) as refused:
        open_bundle(after, trusted={stranger.kid: stranger.public_jwk()["x"]})
    assert refused.value.code == "bundle_untrusted_key"


def test_the_keys_on_record_at_the_migration_are_vouched_for_once(
    api: TestClient, session: Session, owner_engine: Engine
) -> None:
    earlier = MemorySigner(Ed25519PrivateKey.generate(), "file")
    unlisted = MemorySigner(Ed25519PrivateKey.generate(), "file")
    with owner_engine.begin() as connection:  # as the migration found them (the owner writes the list)
        for signer in (earlier, unlisted):
            connection.execute(
                insert(SigningKey.__table__),  # type: ignore[arg-type]
                {
                    "kid": signer.kid,
                    "public_jwk": signer.public_jwk(),
                    "source": "database",
                    "active": False,
                    "created_at": datetime(2026, 1, 5, tzinfo=UTC),
                    "retired_at": datetime(2026, 6, 5, tzinfo=UTC),
                },
            )
        connection.execute(insert(KeyGrandfathered.__table__), {"kid": earlier.kid})  # type: ignore[arg-type]
    paper = _issue(api, "KTU 417 XA", COMPLIANT, COMPLIANT_READINGS)  # the key in force starts signing
    trusted = [row.kid for row in trusted_key_rows(session).rows]
    assert trusted == [earlier.kid, paper["key_id"]]
    statements = session.scalars(select(KeyEndorsement)).all()
    assert [(s.signer_kid, s.subject_kid, s.relation) for s in statements] == [
        (paper["key_id"], earlier.kid, "predecessor")
    ]
    _issue(api, "KTU 418 XA", COMPLIANT, COMPLIANT_READINGS)
    assert len(session.scalars(select(KeyEndorsement)).all()) == 1  # once
    if owner_engine.dialect.name == "postgresql":
        with session.connection() as connection, pytest.raises(Exception, match="permission denied"):
            connection.execute(
                text("INSERT INTO key_grandfathered (kid) VALUES (:kid)"), {"kid": unlisted.kid}
            )


def test_a_withdrawn_key_counts_for_nothing_online_and_cannot_confirm_offline(
    api: TestClient, session: Session, capsys: pytest.CaptureFixture[str]
) -> None:
    old = _issue(api, "KTU 417 XA", COMPLIANT, COMPLIANT_READINGS)
    assert main(["withdraw-signing-key", old["key_id"], "--reason", "laptop stolen"]) == 2
    assert "rotate first" in capsys.readouterr().err
    assert main(["rotate-signing-key"]) == 0
    assert main(["withdraw-signing-key", old["key_id"], "--reason", "laptop stolen"]) == 0
    capsys.readouterr()
    forget_bundles()

    body = _verify_json(api, old)
    assert (body["qr"], body["qr_reason"]) == ("not_genuine", "withdrawn_key")
    page = api.get(f"/verify/{old['number']}?p={quote(old['qr_payload'], safe='')}")
    assert "withdrew because it may have been misused" in page.text
    keys = {key["kid"]: key for key in api.get(KEYS).json()["keys"]}
    assert keys[old["key_id"]]["status"] == "compromised"
    bundle = unpack_bundle(api.get(BUNDLE).text).bundle
    assert bundle.key(old["key_id"]).status == "compromised"  # type: ignore[union-attr]
    assert decide(old["qr_url"], bundle, int(time.time())).code == "compromised"
    assert main(["withdraw-signing-key", old["key_id"], "--reason", "again"]) == 2
    saved = json.loads(api.get(KEYS).text)
    assert [key["status"] for key in saved["keys"]] == ["active", "compromised"]


def test_a_police_posts_held_bundle_follows_a_rotation_without_a_new_anchor(
    api: TestClient, tmp_path: Any, capsys: pytest.CaptureFixture[str]
) -> None:
    old = _issue(api, "KTU 417 XA", COMPLIANT, COMPLIANT_READINGS)
    held, incoming = tmp_path / "held.jws", tmp_path / "incoming.jws"
    incoming.write_text(api.get(BUNDLE).text)
    assert main(["trust-bundle", "--from", str(incoming), "--out", str(held), "--anchor", old["key_id"]]) == 0
    assert main(["rotate-signing-key"]) == 0
    new = _issue(api, "KTU 418 XA", COMPLIANT, COMPLIANT_READINGS)
    incoming.write_text(api.get(BUNDLE).text)
    capsys.readouterr()
    # No anchor now: the held bundle's key is pinned, and it handed over to the new key.
    assert main(["trust-bundle", "--from", str(incoming), "--out", str(held)]) == 0
    assert unpack_bundle(held.read_text()).kid == new["key_id"]
    code = main(["verify", "--offline", "--bundle", str(held), "--anchor", old["key_id"], new["qr_url"]])
    assert code == 0, capsys.readouterr().out
