"""The offline decision on every row of the shared table (tests/trust/offline_cases.py): `decide` and
`trikecert verify --offline` give the row's code, and the command line's exit status and words say
what an officer would read."""

from __future__ import annotations

from pathlib import Path

import pytest
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey
from fastapi.testclient import TestClient
from offline_cases import Case, bundle_payload, offline_cases, resign, trust_anchor
from sqlalchemy.orm import Session

from app.cli import main
from app.trust.bundle import BundleRefused, open_bundle, sign_bundle, unpack_bundle
from app.trust.offline import decide, offline_words
from app.trust.signer import MemorySigner

EXIT = {"certified": 0, "not_genuine": 1, "refusal": 3, "revoked": 3, "superseded": 3, "expired": 3}


@pytest.fixture
def cases(api: TestClient, session: Session) -> list[Case]:
    return offline_cases(api, session)


def _held(bundle_text: str) -> object:
    """What a checker that trusts this service's key holds after taking the bundle in (None: refused)."""
    signer = trust_anchor()
    try:
        return open_bundle(bundle_text, trusted={signer.kid: signer.public_jwk()["x"]}).bundle
    except BundleRefused:
        return None


def test_decide_gives_every_row_its_code(cases: list[Case]) -> None:
    found = {
        case.name: decide(case.payload_text, _held(case.bundle_text), case.now_unix).code for case in cases
    }
    assert found == {case.name: case.expected_code for case in cases}


def test_the_command_line_decides_every_row_alike(
    cases: list[Case], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    anchor = trust_anchor().kid
    for index, case in enumerate(cases):
        bundle = tmp_path / f"bundle-{index}.jws"
        bundle.write_text(case.bundle_text)
        code = main(
            [
                "verify",
                "--offline",
                "--bundle",
                str(bundle),
                "--anchor",
                anchor,
                "--now",
                str(case.now_unix),
                case.payload_text,
            ]
        )
        out, _err = capsys.readouterr()
        words = offline_words(case.expected_code)
        assert f"{words.headline} ({case.expected_code})\n{words.sentence}\n" in out, (case.name, out)
        assert code == EXIT.get(case.expected_code, 4), (case.name, out)


def test_a_paper_shows_its_plate_number_and_the_lists_time(
    cases: list[Case], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    certified = next(case for case in cases if case.name == "certificate (QR URL)")
    bundle = tmp_path / "bundle.jws"
    bundle.write_text(certified.bundle_text)
    code = main(
        [
            "verify",
            "--offline",
            "--bundle",
            str(bundle),
            "--anchor",
            trust_anchor().kid,
            certified.payload_text,
        ]
    )
    out, _err = capsys.readouterr()
    assert code == 0
    assert out.startswith(
        "VALID CERTIFICATE (certified)\nA certificate in force: the vehicle is certified as below.\n"
    )
    assert "registration: KTU 417 XA (compare with the plate)\n" in out
    assert "Certified for the driver and up to one passenger\n" in out
    assert "Checked against the list of " in out


def test_without_an_anchor_the_command_line_decides_nothing(
    cases: list[Case], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bundle = tmp_path / "bundle.jws"
    bundle.write_text(cases[0].bundle_text)
    code = main(["verify", "--offline", "--bundle", str(bundle), cases[0].payload_text])
    out, err = capsys.readouterr()
    assert code == 4
    assert "no trust anchor: give --anchor KID" in err
    assert out.startswith("CANNOT CONFIRM (no_bundle)\n")


def test_a_bundle_taken_in_never_replaces_the_held_one_when_it_fails(
    cases: list[Case], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    anchor = trust_anchor().kid
    good = cases[0].bundle_text
    held = tmp_path / "held.jws"
    source = tmp_path / "incoming.jws"
    source.write_text(good)
    assert main(["trust-bundle", "--from", str(source), "--out", str(held), "--anchor", anchor]) == 0
    assert held.read_text() == good
    capsys.readouterr()

    broken = next(case.bundle_text for case in cases if case.name == "bundle whose signature fails")
    source.write_text(broken)
    assert main(["trust-bundle", "--from", str(source), "--out", str(held)]) == 4
    _out, err = capsys.readouterr()
    assert "The list held before is kept" in err
    assert held.read_text() == good
    payload = bundle_payload(good)
    for change, words in (
        ({"seq": payload["seq"] - 1}, "The list received is older than the one held"),
        ({"authority": "Another Authority"}, "The list received is from another authority"),
        ({"issuer": "trikecert.elsewhere.example"}, "The list received is from another authority"),
    ):
        source.write_text(resign({**payload, **change}))
        assert main(["trust-bundle", "--from", str(source), "--out", str(held)]) == 4
        _out, err = capsys.readouterr()
        assert words in err
        assert held.read_text() == good
    stranger = MemorySigner(Ed25519PrivateKey.generate(), "file")
    entry = {**payload["keys"][0], "kid": stranger.kid, "x": stranger.public_jwk()["x"]}
    source.write_text(
        sign_bundle({**payload, "seq": payload["seq"] + 1, "keys": [entry]}, kid=stranger.kid, key=stranger)
    )
    assert main(["trust-bundle", "--from", str(source), "--out", str(held)]) == 4
    _out, err = capsys.readouterr()
    assert "signed with a key this device has no reason to trust" in err
    assert held.read_text() == good
    newer = resign({**payload, "seq": payload["seq"] + 1})
    source.write_text(newer)
    assert main(["trust-bundle", "--from", str(source), "--out", str(held)]) == 0
    assert held.read_text() == newer
    assert unpack_bundle(newer).bundle.seq == payload["seq"] + 1
