"""What a certificate certifies, frozen at issue time: vehicle, inspection, readings, Table 4, verdict.

The snapshot is stored with the certificate (JSON, decimals as text) and is what the PDF and the
public verify page show, so a later change to a vehicle or an inspection never alters a certificate.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from datetime import date, datetime
from decimal import Decimal
from typing import Any

from sqlalchemy.orm import Session

from app.certificates.actors import officer_of, station_shown_as
from app.dynamics.facts import EstimateFacts, estimate_facts, estimates_from_json
from app.inspections.models import Inspection
from app.remedies.service import stored_assessment
from app.stability import Layout, case_label
from app.stability.model import layout_of_rules
from app.stability.remedies import Advice, advice_of, size_remedies
from app.web.formatting import NOT_RECORDED
from app.wording import occupancy_sentence, remedies_sentence, verdict_sentence

# Every layout's wheels, front first (a delta's print in the order they always did).
WHEEL_NAMES = {
    "front_kg": "Front wheel",
    "left_front_kg": "Left front wheel",
    "right_front_kg": "Right front wheel",
    "left_rear_kg": "Left rear wheel",
    "right_rear_kg": "Right rear wheel",
    "rear_kg": "Rear wheel",
    "overall_kg": "Overall weight",
}


@dataclass(frozen=True)
class VehicleFacts:
    """The vehicle as registered when the certificate was issued."""

    registration_number: str
    make: str
    model: str
    model_year: int | None
    chassis_number: str | None


@dataclass(frozen=True)
class InspectionFacts:
    """Where, when and by whom the vehicle was weighed."""

    id: int
    weighed_at: datetime
    station: str | None
    officer: str | None  # the officer who recorded it, by name and badge (an email in older snapshots)
    scale_calibration: str | None
    rules_version: str
    occupant_mass_kg: Decimal


@dataclass(frozen=True)
class ReadingFacts:
    """One wheel's averaged reading and the spread of its repeated readings (kg)."""

    wheel: str
    name: str
    mean_kg: Decimal
    count: int
    spread_kg: Decimal


@dataclass(frozen=True)
class CaseFacts:
    """One row of Table 4 as decided at inspection time."""

    occupants: int
    label: str
    total_kg: Decimal
    rear_kg: Decimal
    lsf: Decimal
    variance: Decimal
    compliant: bool
    measured: bool


@dataclass(frozen=True)
class Facts:
    """Everything a certificate states about the vehicle and its verdict."""

    authority: str
    vehicle: VehicleFacts
    inspection: InspectionFacts
    readings: tuple[ReadingFacts, ...]
    cases: tuple[CaseFacts, ...]
    compliant: bool
    max_compliant_occupants: int
    verdict: str
    occupancy: str
    issued_by: str | None = None  # by name and badge; None in snapshots made before it was kept
    estimates: EstimateFacts | None = None  # beyond the static test, shown, never certified
    # A refusal's advised remedies at the default target and ballast position; None on a certificate
    # and in snapshots made before remedies were sized.
    remedies: Advice | None = None

    @property
    def remedies_sentence(self) -> str | None:
        """What would make the vehicle comply, in the one wording of the pages."""
        return None if self.remedies is None else remedies_sentence(self.remedies, self.axles)

    @property
    def axles(self) -> Layout:
        """The vehicle's axle layout, named by the rules version its verdict was decided under."""
        return layout_of_rules(self.inspection.rules_version)

    @property
    def recorded_by(self) -> str:
        """Who recorded the weighing, as the document prints it: the officer, else the station."""
        if self.inspection.officer:
            return self.inspection.officer
        return station_shown_as(self.inspection.station) if self.inspection.station else NOT_RECORDED

    @property
    def issuer(self) -> str:
        """Who issued the document, as it prints it."""
        return self.issued_by or NOT_RECORDED

    @property
    def calibration(self) -> str:
        """The scale's calibration in force at the weighing, or 'Not recorded' when there was none."""
        return self.inspection.scale_calibration or NOT_RECORDED

    @property
    def failing_cases(self) -> tuple[CaseFacts, ...]:
        """The loading cases that do not comply."""
        return tuple(case for case in self.cases if not case.compliant)

    def to_json(self) -> dict[str, Any]:
        """A JSON-ready dict: decimals and times as text."""
        plain: dict[str, Any] = _plain(asdict(self))
        return plain

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> Facts:
        """The facts back from their stored JSON; the verdict and occupancy worded as everywhere today."""
        # The stored sentences are the wording of the day of issue (and stay in the stored PDF); the
        # pages, the API and the CLI word the frozen cases afresh so that one fact reads one way.
        inspection = dict(data["inspection"])
        inspection["weighed_at"] = datetime.fromisoformat(inspection["weighed_at"])
        inspection["occupant_mass_kg"] = Decimal(inspection["occupant_mass_kg"])
        cases = tuple(
            CaseFacts(
                occupants=c["occupants"],
                label=c["label"],
                total_kg=Decimal(c["total_kg"]),
                rear_kg=Decimal(c["rear_kg"]),
                lsf=Decimal(c["lsf"]),
                variance=Decimal(c["variance"]),
                compliant=c["compliant"],
                measured=c["measured"],
            )
            for c in data["cases"]
        )
        best = data["max_compliant_occupants"]
        return cls(
            authority=data["authority"],
            vehicle=VehicleFacts(**data["vehicle"]),
            inspection=InspectionFacts(**inspection),
            readings=tuple(
                ReadingFacts(
                    wheel=r["wheel"],
                    name=r["name"],
                    mean_kg=Decimal(r["mean_kg"]),
                    count=r["count"],
                    spread_kg=Decimal(r["spread_kg"]),
                )
                for r in data["readings"]
            ),
            cases=cases,
            compliant=data["compliant"],
            max_compliant_occupants=best,
            verdict=verdict_sentence([(c.occupants, c.compliant) for c in cases], best),
            occupancy=occupancy_sentence(data["compliant"], best),
            issued_by=data.get("issued_by"),
            estimates=estimates_from_json(data.get("estimates")),
            remedies=_advice(data.get("remedies")),
        )


def _advice(data: dict[str, Any] | None) -> Advice | None:
    """The advised remedies back from their stored JSON (decimals as text)."""
    if data is None:
        return None

    def figure(name: str) -> Decimal | None:
        return None if data[name] is None else Decimal(data[name])

    return Advice(
        target_occupants=data["target_occupants"],
        compliant=data["compliant"],
        max_compliant_occupants=data["max_compliant_occupants"],
        ballast_x_m=Decimal(data["ballast_x_m"]),
        ballast_kg=figure("ballast_kg"),
        ballast_possible=data["ballast_possible"],
        seat_shift_m=figure("seat_shift_m"),
        seat_shift_unfixable=tuple(data["seat_shift_unfixable"]),
        tyre_ratio=figure("tyre_ratio"),
    )


def _plain(value: Any) -> Any:
    if isinstance(value, dict):
        return {key: _plain(item) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(item) for item in value]
    if isinstance(value, Decimal):
        return str(value)
    if isinstance(value, datetime):
        return value.isoformat()
    return value


def _readings(inspection: Inspection) -> tuple[ReadingFacts, ...]:
    means = {wheel: getattr(inspection, wheel) for wheel in WHEEL_NAMES}
    raw: dict[str, list[Decimal]] = {}
    for reading in inspection.readings:
        if reading.case_occupants == 0:
            raw.setdefault(reading.wheel, []).append(reading.value_kg)
    return tuple(
        ReadingFacts(
            wheel=wheel,
            name=name,
            mean_kg=mean,
            count=len(raw[wheel]),
            spread_kg=max(raw[wheel]) - min(raw[wheel]),
        )
        for wheel, name in WHEEL_NAMES.items()
        if (mean := means[wheel]) is not None and raw.get(wheel)
    )


def _day(value: date) -> str:
    return f"{value.day} {value:%B %Y}"


def calibration_words(certificate: str | None, valid_until: date | None) -> str | None:
    """The calibration as printed: whatever part of it is on record; None only when none of it is."""
    if certificate and valid_until:
        return f"{certificate}, valid until {_day(valid_until)}"
    if certificate:
        return f"{certificate} (validity not recorded)"
    if valid_until:
        return f"valid until {_day(valid_until)} (certificate number not recorded)"
    return None


def facts_of(
    session: Session,
    inspection: Inspection,
    *,
    authority: str,
    issued_by: str | None = None,
    ballast_x_m: Decimal = Decimal("0.30"),
) -> Facts:
    """The snapshot of an inspection's facts to certify; `issued_by` names the issuer as printed.

    A refusal also keeps its remedies, sized for every seat filled with ballast at `ballast_x_m`.
    """
    vehicle = inspection.vehicle
    officer = officer_of(session, inspection)
    cases = tuple(
        CaseFacts(
            occupants=row.occupants,
            label=case_label(row.occupants),
            total_kg=row.total_kg,
            rear_kg=row.rear_kg,
            lsf=row.lsf,
            variance=row.variance,
            compliant=row.compliant,
            measured=row.measured,
        )
        for row in inspection.loading_cases
    )
    return Facts(
        authority=authority,
        vehicle=VehicleFacts(
            registration_number=inspection.registration_number,  # as weighed
            make=vehicle.make,
            model=vehicle.model,
            model_year=vehicle.model_year,
            chassis_number=vehicle.chassis_number,
        ),
        inspection=InspectionFacts(
            id=inspection.id,
            weighed_at=inspection.created_at,
            station=inspection.station.name if inspection.station else None,
            officer=officer.shown_as() if officer else None,
            scale_calibration=calibration_words(
                inspection.calibration_certificate, inspection.calibration_valid_until
            ),
            rules_version=inspection.rules_version,
            occupant_mass_kg=inspection.occupant_mass_kg,
        ),
        readings=_readings(inspection),
        cases=cases,
        compliant=inspection.compliant,
        max_compliant_occupants=inspection.max_compliant_occupants,
        verdict=verdict_sentence(
            [(c.occupants, c.compliant) for c in cases], inspection.max_compliant_occupants
        ),
        occupancy=occupancy_sentence(inspection.compliant, inspection.max_compliant_occupants),
        issued_by=issued_by,
        estimates=estimate_facts(inspection),
        remedies=None
        if inspection.compliant
        else advice_of(size_remedies(stored_assessment(inspection), ballast_x_m=ballast_x_m)),
    )
