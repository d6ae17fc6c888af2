"""The /check page as served: one page with scripts (its own policy), every other page script-free,
its files and worker and manifest, its words from app/trust/offline.py, the vendored libraries."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient

from app.checker.words import checker_words
from app.trust.offline import CODES, checked_against, offline_words

REPO = Path(__file__).resolve().parents[2]
VENDOR = REPO / "app" / "checker" / "static" / "vendor"
VENDORED = {
    "jsQR.js": "jsqr/dist/jsQR.js",
    "jsQR.LICENSE": "jsqr/LICENSE",
    "noble-ed25519.js": "@noble/ed25519/index.js",
    "noble-ed25519.LICENSE": "@noble/ed25519/LICENSE",
}


def words_in(html: str) -> dict[str, Any]:
    found = re.search(r'<script type="application/json" id="check-words">(.*?)</script>', html, re.S)
    assert found is not None
    words: dict[str, Any] = json.loads(found.group(1))
    return words


def test_check_redirects_into_the_workers_scope(client: TestClient) -> None:
    response = client.get("/check", follow_redirects=False)
    assert response.status_code == 308
    assert response.headers["location"] == "/check/"


def test_the_page_alone_may_run_scripts_from_its_own_origin(client: TestClient) -> None:
    page = client.get("/check/")
    assert page.status_code == 200
    policy = page.headers["content-security-policy"]
    assert "script-src 'self'" in policy
    assert "worker-src 'self'" in policy
    assert "connect-src 'self'" in policy
    assert "unsafe" not in policy
    for other in ("/login", "/verify"):
        answer = client.get(other)
        assert "script-src 'none'" in answer.headers["content-security-policy"], other
        assert "<script" not in answer.text, other


def test_the_words_come_from_the_offline_wording(client: TestClient) -> None:
    words = words_in(client.get("/check/").text)
    assert words == json.loads(json.dumps(checker_words()))
    for code in CODES:
        said = offline_words(code)
        assert words["codes"][code] == {
            "headline": said.headline,
            "sentence": said.sentence,
            "tone": said.tone,
        }
    assert words["codes"]["stale"]["sentence"].startswith("Cannot confirm: connect to update the list")
    when = checked_against(1_796_100_000)
    prefix = words["checked_against"]["prefix"]
    assert when.startswith(prefix)
    assert prefix == "Checked against the list of "
    assert len(words["occupancy"]["certificate"]) == 100


def test_the_scripts_contain_no_sentence_of_the_verdicts() -> None:
    scripts = "".join(path.read_text() for path in (REPO / "app/checker/static").glob("*.js"))
    for code in (*CODES, "bundle_rollback"):
        said = offline_words(code)
        assert said.headline not in scripts.replace("CANNOT", "")  # codes, never their words
        assert said.sentence not in scripts


def test_the_worker_keeps_the_page_and_its_files(client: TestClient) -> None:
    worker = client.get("/check/sw.js")
    assert worker.status_code == 200
    assert worker.headers["content-type"].startswith("text/javascript")
    assert worker.headers["cache-control"] == "no-cache"
    listed = re.search(r"const KEEP = (\[.*?\]);", worker.text)
    assert listed is not None
    keep = json.loads(listed.group(1))
    assert {"/check/", "/static/app.css", "/check/static/check.js", "/check/static/decide.js"} <= set(keep)
    assert "/check/static/vendor/jsQR.js" in keep
    for url in keep:
        assert client.get(url).status_code == 200, url


def test_the_manifest_installs_the_page(client: TestClient) -> None:
    manifest = client.get("/check/manifest.webmanifest")
    assert manifest.headers["content-type"].startswith("application/manifest+json")
    body = manifest.json()
    assert body["start_url"] == body["scope"] == "/check/"
    assert {icon["sizes"] for icon in body["icons"]} == {"192x192", "512x512"}
    for icon in body["icons"]:
        assert client.get(icon["src"]).headers["content-type"] == "image/png"


def test_no_file_outside_the_pages_folder_is_served(client: TestClient) -> None:
    for name in ("../views.py", "..%2Fviews.py", "sw.js", "nothing.js", "../../../pyproject.toml"):
        assert client.get(f"/check/static/{name}").status_code == 404, name


def test_the_licences_are_served_beside_the_libraries(client: TestClient) -> None:
    assert "Apache License" in client.get("/check/static/vendor/jsQR.LICENSE").text
    assert "MIT License" in client.get("/check/static/vendor/noble-ed25519.LICENSE").text


@pytest.mark.parametrize(("copy", "original"), sorted(VENDORED.items()))
def test_the_vendored_copy_is_node_modules_file(copy: str, original: str) -> None:
    source = REPO / "node_modules" / original
    if not source.is_file():
        pytest.skip(f"node_modules/{original} is not installed (npm ci)")
    assert (VENDOR / copy).read_bytes() == source.read_bytes(), "run tools/vendor_checker.sh"
