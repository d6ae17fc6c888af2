"""The reader chooses the pages' language: the switcher's cookie, else Accept-Language; the API stays
English; shared caches are told the pages vary by both."""

from __future__ import annotations

import re

import pytest
from fastapi.testclient import TestClient

HTML = {"Accept": "text/html"}
LANG_TAGS = {"en": "en-GB", "ha": "ha", "yo": "yo", "ig": "ig", "pcm": "pcm"}
SKIP_LINK = {
    "en": "Skip to main content",
    "ha": "Tsallaka zuwa babban abin ciki",
    "yo": "Fo lọ sí àkóónú pàtàkì",
    "ig": "Wụga gaa n'isi ọdịnaya",
    "pcm": "Jump go di main tin",
}
NOT_FOUND = {
    "en": "Page not found",
    "ha": "Ba a sami shafin ba",
    "yo": "A kò rí ojú-ìwé náà",
    "ig": "Ahụghị ibe ahụ",
    "pcm": "We no see dis page",
}


def _html_lang(body: str) -> str:
    found = re.search(r'<html lang="([^"]+)"', body)
    assert found
    return found.group(1)


@pytest.mark.parametrize("locale", list(LANG_TAGS))
@pytest.mark.parametrize("path", ["/login", "/check/", "/no-such-page"])
def test_each_page_speaks_the_accept_language_and_says_so(client: TestClient, path: str, locale: str) -> None:
    response = client.get(path, headers={**HTML, "Accept-Language": f"{locale}-NG, en;q=0.5"})
    assert _html_lang(response.text) == LANG_TAGS[locale]
    assert SKIP_LINK[locale] in response.text
    if path == "/no-such-page":
        assert response.status_code == 404
        assert NOT_FOUND[locale] in response.text
    vary = {v.strip().lower() for v in response.headers["vary"].split(",")}
    assert {"accept-language", "cookie"} <= vary


def test_the_cookie_beats_the_header(client: TestClient) -> None:
    client.cookies.set("trikecert_lang", "yo")
    response = client.get("/login", headers={**HTML, "Accept-Language": "ha"})
    assert _html_lang(response.text) == "yo"


@pytest.mark.parametrize(
    ("cookie", "header"),
    [("xx", None), ("", "xx-YY, zz"), ("en;drop", "q=nonsense,,;;"), ("\x7f", "ha;q=2")],
)
def test_unknown_or_malformed_choices_mean_english(
    client: TestClient, cookie: str, header: str | None
) -> None:
    headers = {**HTML, "Cookie": f"trikecert_lang={cookie}"}
    if header is not None:
        headers["Accept-Language"] = header
    response = client.get("/login", headers=headers)
    assert response.status_code == 200
    assert _html_lang(response.text) == "en-GB"


def test_the_switcher_names_each_language_in_itself_and_marks_the_current(client: TestClient) -> None:
    body = client.get("/login?next=/inspections", headers={**HTML, "Accept-Language": "ig"}).text
    switcher = body.split('class="languages"', 1)[1].split("</nav>", 1)[0]
    for code, name in [
        ("en", "English"),
        ("ha", "Hausa"),
        ("yo", "Yorùbá"),
        ("ig", "Igbo"),
        ("pcm", "Naijá"),
    ]:
        tag = LANG_TAGS[code]
        link = re.search(
            rf'<a href="/language/{code}\?next=([^"]+)" lang="{tag}" hreflang="{tag}"([^>]*)>{name}</a>',
            switcher,
        )
        assert link, code
        assert link.group(1) == "/login%3Fnext%3D/inspections"
        assert ("aria-current" in link.group(2)) == (code == "ig")


def test_choosing_a_language_remembers_it_for_a_year_and_goes_back(client: TestClient) -> None:
    response = client.get("/language/ha?next=/check/", follow_redirects=False)
    assert response.status_code == 303
    assert response.headers["location"] == "/check/"
    cookie = response.headers["set-cookie"]
    assert cookie.startswith("trikecert_lang=ha;")
    assert "Max-Age=31536000" in cookie
    assert "Path=/" in cookie
    assert "SameSite=lax" in cookie
    assert _html_lang(client.get("/login", headers=HTML).text) == "ha"


@pytest.mark.parametrize(
    "target", [None, "", "https://evil.example/", "//evil.example/", "/\\evil.example", "evil", "/ok\r\nX: y"]
)
def test_the_switcher_only_sends_back_to_this_site(client: TestClient, target: str | None) -> None:
    params = {} if target is None else {"next": target}
    response = client.get("/language/yo", params=params, follow_redirects=False)
    assert response.status_code == 303
    assert response.headers["location"] == "/"


def test_an_unknown_language_is_not_found(client: TestClient) -> None:
    response = client.get("/language/fr?next=/", headers=HTML, follow_redirects=False)
    assert response.status_code == 404
    assert "set-cookie" not in response.headers


def test_the_api_stays_english(client: TestClient) -> None:
    client.cookies.set("trikecert_lang", "ha")  # as a browser that chose Hausa on the pages sends it
    response = client.get("/api/v1/no-such-thing", headers={"Accept-Language": "ha"})
    assert response.status_code == 404
    assert "Ba a" not in response.text
    assert "accept-language" not in response.headers.get("vary", "").lower()
