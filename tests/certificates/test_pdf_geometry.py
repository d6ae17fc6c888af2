"""The PDF holds for every input the API accepts: no text box overlaps another, a graphic or the page edge.

Documents are issued through the station API; the PDF is read back with poppler's `pdftotext`
(`-bbox` for every word's box, plain for the text) and the layout's own record of where it drew
the QR code and the chart, taken from the same render as the stored bytes.
"""

from __future__ import annotations

import logging
import re
import shutil
import subprocess
import xml.etree.ElementTree as ET
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any

import pytest
from certificate_helpers import FRONT_HEAVY, FRONT_HEAVY_READINGS, certify, register, weigh
from fastapi.testclient import TestClient
from needed_tools import tool_missing
from sqlalchemy.orm import Session
from study_data import STUDY_READINGS, STUDY_VEHICLE

import app.certificates.service as service
from app.certificates.actors import Actor
from app.certificates.pdf import CertificateDocument, render_with_layout
from app.certificates.service import revoke_certificate
from app.config import get_settings
from app.documents.layout import MARGIN, Layout, Region
from app.stations.details import StationDetails
from app.stations.service import create_station

MM = 72 / 25.4  # points per mm
YORUBA_MAKE = "Ṣàngó Motors"
YORUBA_STATION = "Ọ̀yọ́ weighbridge"
CJK = "巴贾杰"
# The chart's own words: inside its region nothing else may stand.
CHART_WORDS = re.compile(
    r"^(LSF|Shaded:|unstable|\(LSF|at|or|above|2/3\)|limit|2/3|C|NC|Empty|Driver|\+\d+|Loading|case|"
    r"\(occupants\)|\d\.\d\d)$"
)
# The stability map's own words (estimates beyond the static test).
MAP_WORDS = re.compile(
    r"^(Rollover|threshold|\(g\)|Circle:|C\.|Cross:|NC\.|Shaded:|yaw-unstable\.|limit|2/3|LSF|Empty|Driver|"
    r"\+\d+|minimum|g|\d\.\d\d?)$"
)
REGION_WORDS = {"chart": CHART_WORDS, "map": MAP_WORDS}


@dataclass(frozen=True)
class Word:
    """A word as poppler reads it back, its box in points from the page's top left."""

    page: int
    text: str
    x0: float
    y0: float
    x1: float
    y1: float

    def inside(self, region: Region) -> bool:
        """True when the word lies wholly within the region."""
        x, y = region.x * MM, region.y * MM
        return x <= self.x0 and self.x1 <= x + region.w * MM and y <= self.y0 and self.y1 <= y + region.h * MM

    def overlaps(self, other: Word | Region) -> bool:
        """True when the two boxes share area (touching edges do not count)."""
        if isinstance(other, Region):
            box = (other.x * MM, other.y * MM, (other.x + other.w) * MM, (other.y + other.h) * MM)
        else:
            box = (other.x0, other.y0, other.x1, other.y1)
        eps = 0.05
        return (
            self.x0 < box[2] - eps
            and box[0] < self.x1 - eps
            and self.y0 < box[3] - eps
            and box[1] < self.y1 - eps
        )


def pdftotext(*args: str, pdf: bytes) -> str:
    """Run poppler's pdftotext on the PDF bytes and return what it prints."""
    binary = shutil.which("pdftotext")
    if binary is None:
        tool_missing("pdftotext", "apt-get install poppler-utils")
    done = subprocess.run([binary, *args, "-", "-"], input=pdf, capture_output=True, check=True)
    return done.stdout.decode("utf-8")


def words_of(pdf: bytes) -> tuple[list[Word], list[tuple[float, float]]]:
    """Every word with its box, and each page's size (points)."""
    xhtml = pdftotext("-bbox", pdf=pdf)
    root = ET.fromstring(xhtml)
    ns = {"x": "http://www.w3.org/1999/xhtml"}
    words, sizes = [], []
    for number, page in enumerate(root.iterfind(".//x:page", ns), start=1):
        sizes.append((float(page.attrib["width"]), float(page.attrib["height"])))
        for word in page.iterfind("x:word", ns):
            words.append(
                Word(
                    number,
                    word.text or "",
                    float(word.attrib["xMin"]),
                    float(word.attrib["yMin"]),
                    float(word.attrib["xMax"]),
                    float(word.attrib["yMax"]),
                )
            )
    return words, sizes


@dataclass
class Rendered:
    """A certificate as issued: its JSON, the served PDF and the layout of the same render."""

    body: dict[str, Any]
    pdf: bytes
    layout: Layout


@pytest.fixture
def layouts(monkeypatch: pytest.MonkeyPatch) -> list[tuple[bytes, Layout]]:
    """Record the layout of every PDF the service renders."""
    seen: list[tuple[bytes, Layout]] = []

    def spy(document: CertificateDocument) -> bytes:
        pdf, layout = render_with_layout(document)
        seen.append((pdf, layout))
        return pdf

    monkeypatch.setattr(service, "render_pdf", spy)
    return seen


def issued(api: TestClient, layouts: list[tuple[bytes, Layout]], inspection_id: int) -> Rendered:
    """Certify an inspection and fetch the PDF the service stored."""
    body = certify(api, inspection_id)
    response = api.get(f"/api/v1/certificates/{body['number']}/pdf")
    assert response.status_code == 200
    rendered, layout = layouts[-1]
    assert response.content == rendered  # the layout is the one of the stored bytes
    return Rendered(body, response.content, layout)


def assert_holds(document: Rendered) -> list[Word]:
    """No word leaves the page or overlaps another word, the QR code or the chart's area."""
    words, sizes = words_of(document.pdf)
    assert words
    for word in words:
        width, height = sizes[word.page - 1]
        assert 5 * MM <= word.x0 < word.x1 <= width - 5 * MM, word
        assert 5 * MM <= word.y0 < word.y1 <= height - 5 * MM, word
    by_page: dict[int, list[Word]] = {}
    for word in words:
        by_page.setdefault(word.page, []).append(word)
    for page_words in by_page.values():
        for i, word in enumerate(page_words):
            for other in page_words[i + 1 :]:
                assert not word.overlaps(other), (word, other)
    regions = document.layout.regions
    assert [r.kind for r in regions if r.kind == "qr"] == ["qr"]
    # The opening block (CERTIFIED / NOT CERTIFIED) is the first thing on the page: its words lie
    # wholly inside it, every other word of page 1 below it.
    [headline] = [r for r in regions if r.kind == "headline"]
    assert (headline.page, headline.y) == (1, MARGIN)
    opening = [word for word in by_page[1] if word.overlaps(headline)]
    assert opening
    assert all(word.inside(headline) for word in opening), opening
    assert all(word.y0 >= (headline.y + headline.h) * MM for word in by_page[1] if word not in opening)
    assert [r.page for r in regions if r.kind == "qr"] == [1]
    assert len([r for r in regions if r.kind == "chart"]) == 1
    for region in regions:
        width, height = sizes[region.page - 1]
        assert region.x > 0, region
        assert (region.x + region.w) * MM < width, region
        assert region.y > 0, region
        assert (region.y + region.h) * MM < height, region
        for word in by_page.get(region.page, []):
            if region.kind in REGION_WORDS and REGION_WORDS[region.kind].match(word.text):
                continue
            if region.kind == "headline" and word.inside(region):
                continue
            assert not word.overlaps(region), (word, region)
    for i, first in enumerate(regions):
        for second in regions[i + 1 :]:
            if first.page == second.page:
                assert not (
                    first.x < second.x + second.w
                    and second.x < first.x + first.w
                    and first.y < second.y + second.h
                    and second.y < first.y + first.h
                ), (first, second)
    return words


def squeezed(text: str) -> str:
    """The text without any whitespace: a wrapped value reads back whole once the breaks are gone."""
    return re.sub(r"\s+", "", text)


EXTREME_VEHICLE: dict[str, Any] = {
    "registration_number": "ABCDEFGH12345678",
    "make": (YORUBA_MAKE + " " + "Ẹ̀gbá Ìjẹ̀ṣà ɓɗƙŋ " * 6)[:80],
    "model": ("Keke " + CJK + " " + "W" * 80)[:80],
    "model_year": 2026,
    "chassis_number": "M" * 64,
    "wheelbase_m": 2.0,
    "seats": [{"role": "driver", "x_m": 0.9303}] + [{"role": "passenger", "x_m": 1.6303}] * 11,
}


def twenty(value: float) -> list[float]:
    """Twenty readings of a wheel, spread by at most 1.9 kg (within the default limit of 2 kg)."""
    return [round(value + (i % 20) * 0.1, 1) for i in range(20)]


def extreme_inspection() -> dict[str, Any]:
    """The most the API accepts on one weighing: 20 readings per wheel, 10 load items, 12 measured cases."""
    readings = {
        "front_kg": twenty(1000),
        "left_rear_kg": twenty(600),
        "right_rear_kg": twenty(700),
    }
    return {
        "registration_number": EXTREME_VEHICLE["registration_number"],
        "readings": readings,
        "load_items": [{"label": f"Load {i} " + "ọ" * 52, "mass_kg": 1000, "x_m": 1.5} for i in range(10)],
        "measured_cases": [
            {
                "occupants": n,
                "readings": {
                    "front_kg": 1001 + 20 * n,
                    "left_rear_kg": 601 + 21 * n,
                    "right_rear_kg": 701 + 21 * n,
                },
            }
            for n in range(1, 13)
        ],
    }


@pytest.fixture
def extreme_api(client: TestClient, session: Session) -> TestClient:
    """A station whose name and calibration certificate are as long as the API accepts."""
    name = (YORUBA_STATION + " " + CJK + " " + "Ìbàdàn ṣọ́ọ̀bù " * 10)[:120]
    _station, key = create_station(
        session,
        name=name,
        details=StationDetails(calibration_certificate="C" * 64),
    )
    client.headers["Authorization"] = f"Bearer {key}"
    return client


def test_the_extreme_certificate_wraps_breaks_pages_and_overlaps_nothing(
    extreme_api: TestClient, layouts: list[tuple[bytes, Layout]], caplog: pytest.LogCaptureFixture
) -> None:
    register(extreme_api, EXTREME_VEHICLE)
    inspection = extreme_api.post("/api/v1/inspections", json=extreme_inspection())
    assert inspection.status_code == 201, inspection.text
    assert len(inspection.json()["loading_cases"]) == 13
    with caplog.at_level(logging.WARNING, logger="trikecert.certificates.pdf"):
        document = issued(extreme_api, layouts, inspection.json()["id"])
    words = assert_holds(document)
    assert max(word.page for word in words) == 2
    text = pdftotext(pdf=document.pdf)
    lines = text.splitlines()
    assert any(line.startswith(YORUBA_MAKE) for line in lines), text
    assert any(line.startswith(YORUBA_STATION) for line in lines), text
    flat = squeezed(text)
    make = EXTREME_VEHICLE["make"]
    assert squeezed(make) in flat
    assert squeezed(EXTREME_VEHICLE["chassis_number"]) in flat
    assert squeezed(EXTREME_VEHICLE["model"].replace(CJK, "\ufffd" * 3)) in flat
    assert "?" not in text.replace("?p=", "")
    assert "Driver + 11 passengers *" in text
    assert "Page 2 of 2" in text
    assert f"{document.body['number']} (continued)" in text
    warnings = [r.getMessage() for r in caplog.records if "drawn as U+FFFD" in r.getMessage()]
    assert len(warnings) == 1
    assert "U+5DF4" in warnings[0]


def test_a_revoked_two_page_certificate_is_stamped_on_every_page_within_the_margins(
    extreme_api: TestClient, session: Session, layouts: list[tuple[bytes, Layout]]
) -> None:
    register(extreme_api, EXTREME_VEHICLE)
    inspection = extreme_api.post("/api/v1/inspections", json=extreme_inspection())
    assert inspection.status_code == 201, inspection.text
    document = issued(extreme_api, layouts, inspection.json()["id"])
    number = document.body["number"]
    revoke_certificate(session, number=number, actor=Actor.of_cli(), reason="Wrong wheel readings")
    stamped = extreme_api.get(f"/api/v1/certificates/{number}/pdf").content
    assert stamped.startswith(document.pdf)
    before, _sizes = words_of(document.pdf)
    after, sizes = words_of(stamped)
    original = {(w.page, w.text, round(w.x0), round(w.y0)) for w in before}
    stamp = [w for w in after if (w.page, w.text, round(w.x0), round(w.y0)) not in original]
    assert {w.page for w in stamp} == {1, 2}
    for page in (1, 2):
        band = [w for w in stamp if w.page == page and w.y1 <= MARGIN * MM]
        line = " ".join(w.text for w in sorted(band, key=lambda w: (round(w.y0), w.x0)))
        assert line.startswith("REVOKED on "), line
        assert "Wrong wheel readings" in line
        across = [w.text for w in stamp if w.page == page and w not in band]  # read letter by letter
        assert sorted("".join(across)) == sorted("REVOKED"), across
        width, height = sizes[page - 1]
        for word in band:
            assert 5 * MM <= word.x0 < word.x1 <= width - 5 * MM, word
            assert 5 * MM <= word.y0 < word.y1 <= height - 5 * MM, word
            # The band stands in the top margin: it hides none of the document's words.
            assert not any(word.overlaps(other) for other in before if other.page == page), word


def test_the_study_refusal_is_one_page_and_overlaps_nothing(
    api: TestClient, layouts: list[tuple[bytes, Layout]]
) -> None:
    register(api)
    document = issued(api, layouts, weigh(api))
    words = assert_holds(document)
    assert {word.page for word in words} == {1}
    assert "Page 1 of 1" in pdftotext(pdf=document.pdf)


def test_a_certificate_with_yoruba_names_reads_back_exactly(
    client: TestClient, session: Session, layouts: list[tuple[bytes, Layout]]
) -> None:
    _station, key = create_station(session, name=YORUBA_STATION)
    client.headers["Authorization"] = f"Bearer {key}"
    register(client, {**FRONT_HEAVY, "make": YORUBA_MAKE, "model": "Ọkọ̀ Ẹlẹ́ṣin ɓɗƙŋ"})
    document = issued(client, layouts, weigh(client, "KTU-417-XA", FRONT_HEAVY_READINGS))
    words = assert_holds(document)
    assert {word.page for word in words} == {1}
    lines = [line.strip() for line in pdftotext(pdf=document.pdf).splitlines()]
    assert YORUBA_MAKE in lines
    assert YORUBA_STATION in lines
    assert "Ọkọ̀ Ẹlẹ́ṣin ɓɗƙŋ" in lines
    assert "Lateral Stability Certificate" in lines


def test_documents_rendered_at_once_in_threads_are_the_same_bytes(
    client: TestClient, session: Session, monkeypatch: pytest.MonkeyPatch
) -> None:
    documents: list[CertificateDocument] = []

    def keep(document: CertificateDocument) -> bytes:
        documents.append(document)
        return render_with_layout(document)[0]

    monkeypatch.setattr(service, "render_pdf", keep)
    _station, key = create_station(session, name=YORUBA_STATION)
    client.headers["Authorization"] = f"Bearer {key}"
    register(client, {**FRONT_HEAVY, "make": YORUBA_MAKE})
    certify(client, weigh(client, "KTU-417-XA", FRONT_HEAVY_READINGS))
    register(client)
    certify(client, weigh(client))
    expected = [render_with_layout(document)[0] for document in documents]
    with ThreadPoolExecutor(max_workers=4) as pool:
        rendered = list(pool.map(lambda d: render_with_layout(d)[0], documents * 6))
    assert rendered == expected * 6


ILLUSTRATIVE_VEHICLE: dict[str, Any] = {
    **STUDY_VEHICLE,
    "seats": [{"role": "driver", "x_m": 0.9303, "z_m": 0.75}]
    + [{"role": "passenger", "x_m": 1.6303, "z_m": 0.8}] * 3,
    "track_m": 1.15,
    "wheel_radius_m": 0.19,
    "front_cornering_stiffness_n_per_rad": 8000,
    "rear_cornering_stiffness_n_per_rad": 8000,
}


@pytest.mark.parametrize("min_rollover", [None, "0.65"])
def test_the_estimates_and_the_stability_map_read_back_and_overlap_nothing(
    api: TestClient,
    layouts: list[tuple[bytes, Layout]],
    monkeypatch: pytest.MonkeyPatch,
    min_rollover: str | None,
) -> None:
    if min_rollover:
        monkeypatch.setenv("TRIKECERT_MIN_ROLLOVER_G", min_rollover)
    get_settings.cache_clear()
    register(api, ILLUSTRATIVE_VEHICLE)
    weighing = {
        "registration_number": "BDG 252 QH",
        "readings": STUDY_READINGS,
        "cg_lift": {"lift_height_m": 0.4, "front_kg": 94.8},
    }
    inspection = api.post("/api/v1/inspections", json=weighing)
    assert inspection.status_code == 201, inspection.text
    document = issued(api, layouts, inspection.json()["id"])
    get_settings.cache_clear()
    assert_holds(document)
    assert [r.kind for r in document.layout.regions].count("map") == 1
    text = squeezed(pdftotext(pdf=document.pdf))
    assert squeezed("Beyond the static test (estimates, not part of the verdict)") in text
    for figure in ("0.5503 m", "0.7277 g", "36.04°", "113.8 km/h", "0.6227 g", "70.0 km/h"):
        assert squeezed(figure) in text, figure
    assert squeezed("None (understeers)") in text
    assert squeezed("Rear track: 1.150 m") in text
    assert (squeezed("minimum 0.65 g") in text) is bool(min_rollover)
