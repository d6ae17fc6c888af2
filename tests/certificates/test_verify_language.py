"""What a machine reads of a paper does not depend on the reader's language: the JSON verification
(both addresses, with a genuine QR payload, a bad one or none) is byte-identical whatever the
Accept-Language or language cookie."""

from __future__ import annotations

from typing import Any
from urllib.parse import quote

import pytest
from certificate_helpers import study_certificate
from fastapi.testclient import TestClient

JSON = {"Accept": "application/json"}
LOCALES = ("ha", "yo", "ig", "pcm")


@pytest.fixture
def issued(api: TestClient) -> dict[str, Any]:
    body = study_certificate(api)
    api.headers.pop("Authorization")  # the verification is public
    return body


@pytest.mark.parametrize("address", ["/api/v1/verify", "/verify"])
def test_the_json_verification_is_the_same_in_every_language(
    issued: dict[str, Any], client: TestClient, address: str
) -> None:
    payload = quote(issued["qr_payload"], safe="")
    for query in ("", f"?p={payload}", "?p=not-a-payload"):
        url = f"{address}/{issued['number']}{query}"
        english = client.get(url, headers=JSON)
        assert english.status_code == 200
        for locale in LOCALES:
            by_header = client.get(url, headers={**JSON, "Accept-Language": locale})
            by_cookie = client.get(url, headers={**JSON, "Cookie": f"trikecert_lang={locale}"})
            assert by_header.content == english.content, (url, locale)
            assert by_cookie.content == english.content, (url, locale)
