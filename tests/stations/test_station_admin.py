"""Stations from the command line: created with their scale, edited, their key rotated (the old one
stops working at once), disabled and enabled again; bad particulars are refused naming the field."""

from __future__ import annotations

from datetime import date
from decimal import Decimal

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session

from app.cli import main as trikecert
from app.errors import InvalidInput
from app.stations.details import StationDetails
from app.stations.models import Station
from app.stations.service import create_station, update_station

INSPECTIONS = "/api/v1/inspections"


def station_named(session: Session, name: str) -> Station:
    session.expire_all()
    return session.scalars(select(Station).where(Station.name == name)).one()


def last_line(capsys: pytest.CaptureFixture[str]) -> str:
    return capsys.readouterr().out.strip().splitlines()[-1]


def works(client: TestClient, key: str) -> int:
    status: int = client.get(INSPECTIONS, headers={"Authorization": f"Bearer {key}"}).status_code
    return status


def test_create_station_records_the_site_and_its_scale(
    client: TestClient, session: Session, capsys: pytest.CaptureFixture[str]
) -> None:
    code = trikecert(
        [
            "create-station", "Agbara  weighbridge",
            "--location", "Lagos-Badagry Expressway, Agbara",
            "--contact", "Mrs A. Okafor, +234 803 555 0100",
            "--calibration-certificate", "SON/CAL/2026/0415",
            "--calibration-valid-until", "2027-03-31",
            "--capacity-kg", "3000",
            "--division-kg", "1",
        ]
    )  # fmt: skip
    key = last_line(capsys)

    assert code == 0
    assert key.startswith("tks_")
    station = station_named(session, "Agbara weighbridge")
    assert station.location == "Lagos-Badagry Expressway, Agbara"
    assert station.operator_contact == "Mrs A. Okafor, +234 803 555 0100"
    assert station.calibration_certificate == "SON/CAL/2026/0415"
    assert station.calibration_valid_until == date(2027, 3, 31)
    assert (station.capacity_kg, station.division_kg) == (Decimal(3000), Decimal(1))
    assert works(client, key) == 200


def test_rotating_the_key_stops_the_old_one_at_once(
    client: TestClient, session: Session, capsys: pytest.CaptureFixture[str]
) -> None:
    assert trikecert(["create-station", "Ojo weighbridge"]) == 0
    old = last_line(capsys)
    assert trikecert(["rotate-station-key", "Ojo weighbridge"]) == 0
    new = last_line(capsys)

    assert new != old
    assert new.startswith("tks_")
    assert works(client, old) == 401
    assert works(client, new) == 200
    assert station_named(session, "Ojo weighbridge").key_rotated_at is not None


def test_a_disabled_station_is_refused_until_enabled(
    client: TestClient, session: Session, capsys: pytest.CaptureFixture[str]
) -> None:
    station, key = create_station(session, name="Ikeja weighbridge")
    assert trikecert(["disable-station", "Ikeja weighbridge"]) == 0
    assert "(disabled)" in capsys.readouterr().out
    assert works(client, key) == 401
    assert trikecert(["enable-station", str(station.id)]) == 0
    assert works(client, key) == 200


def test_update_station_changes_only_what_is_given(
    session: Session, capsys: pytest.CaptureFixture[str]
) -> None:
    create_station(
        session,
        name="Epe weighbridge",
        details=StationDetails(location="Epe", calibration_certificate="OLD-1", capacity_kg=Decimal(1500)),
    )
    code = trikecert(
        ["update-station", "Epe weighbridge", "--calibration-certificate", "NEW-2",
         "--calibration-valid-until", "2027-06-30"]
    )  # fmt: skip

    assert code == 0
    station = station_named(session, "Epe weighbridge")
    assert (station.location, station.capacity_kg) == ("Epe", Decimal(1500))
    assert (station.calibration_certificate, station.calibration_valid_until) == ("NEW-2", date(2027, 6, 30))


@pytest.mark.parametrize(
    ("details", "field"),
    [
        (StationDetails(capacity_kg=Decimal(0)), "capacity_kg"),
        (StationDetails(capacity_kg=Decimal(500), division_kg=Decimal(600)), "division_kg"),
        (StationDetails(division_kg=Decimal("0.0001")), "division_kg"),
        (StationDetails(calibration_certificate="x" * 65), "calibration_certificate"),
        (StationDetails(location="bell\x07"), "location"),
    ],
)
def test_bad_particulars_are_refused_naming_the_field(
    session: Session, details: StationDetails, field: str
) -> None:
    station, _key = create_station(session, name="Badagry weighbridge")
    with pytest.raises(InvalidInput) as refused:
        update_station(session, station=station, details=details)
    assert refused.value.problems[0].field == field


def test_the_command_reports_an_unknown_station(capsys: pytest.CaptureFixture[str], session: Session) -> None:
    assert trikecert(["rotate-station-key", "Nowhere"]) == 2
    assert "no station is named 'Nowhere'" in capsys.readouterr().err
