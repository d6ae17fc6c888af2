"""What a weighing must satisfy about the scale it came from: calibration in force, within capacity,
and settled (repeated readings of one wheel that agree)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from datetime import date, timedelta
from decimal import Decimal

from app.config import get_settings
from app.errors import InvalidInput, ServiceError
from app.stability import WheelReadings
from app.stability.layout import ALL_WHEELS, OVERALL
from app.stations.on_file import StationOnFile

WHEEL_NAMES = {
    "front_kg": "the front wheel",
    "left_rear_kg": "the left rear wheel",
    "right_rear_kg": "the right rear wheel",
    "left_front_kg": "the left front wheel",
    "right_front_kg": "the right front wheel",
    "rear_kg": "the rear wheel",
    "overall_kg": "the whole vehicle",
}
WHEELS = (*ALL_WHEELS, OVERALL)


@dataclass(frozen=True)
class ScaleRules:
    """How far repeated readings may spread, and whether a station must have a calibration on record."""

    max_spread_kg: Decimal = Decimal("2")
    require_calibration: bool = False


def configured_scale_rules() -> ScaleRules:
    """The scale rules under the current settings (TRIKECERT_MAX_READING_SPREAD_KG, ...)."""
    settings = get_settings()
    return ScaleRules(settings.max_reading_spread_kg, settings.require_calibration)


class CalibrationRefused(ServiceError):
    """The station's scale has no calibration in force: its readings are worth nothing in law (403)."""

    status = 403


def check_calibration(station: StationOnFile, *, today: date, rules: ScaleRules) -> None:
    """Refuse a station whose calibration lapsed before `today` (UTC), or is not on record when required."""
    valid_until = station.calibration_valid_until
    if valid_until is None:
        if rules.require_calibration:
            raise CalibrationRefused(
                "calibration_valid_until: no calibration of this station's scale is on record; have it "
                "recorded (certificate and valid-until date) before submitting readings",
                field="calibration_valid_until",
                rule="calibration_missing",
            )
        return
    if valid_until < today:
        certificate = (
            f"certificate {station.calibration_certificate}"
            if station.calibration_certificate
            else "the calibration (no certificate number on record)"
        )
        lapsed = valid_until + timedelta(days=1)
        raise CalibrationRefused(
            f"calibration_valid_until: the calibration of this station's scale lapsed on "
            f"{lapsed.isoformat()}: {certificate} was valid until {valid_until.isoformat()} "
            "(UTC); have the scale recalibrated and the new certificate recorded before submitting readings",
            field="calibration_valid_until",
            rule="calibration_lapsed",
        )


def _field(prefix: str, wheel: str, values: Sequence[Decimal], index: int | None = None) -> str:
    field = f"{prefix}.{wheel}"
    return field if index is None or len(values) == 1 else f"{field}[{index}]"


def _kg(value: Decimal) -> str:
    return f"{value.normalize():f}"


def check_capacity(station: StationOnFile, sets: Sequence[tuple[str, WheelReadings]]) -> None:
    """Refuse any reading above the capacity of the station's scale, naming the reading."""
    capacity = station.capacity_kg
    if capacity is None:
        return
    for prefix, readings in sets:
        for wheel in WHEELS:
            values = readings.values(wheel)
            for index, value in enumerate(values):
                if value.is_finite() and value > capacity:
                    field = _field(prefix, wheel, values, index)
                    raise InvalidInput(
                        f"{field}: {_kg(value)} kg is above the {_kg(capacity)} kg capacity of this "
                        "station's scale; a reading beyond capacity cannot be trusted",
                        field=field,
                        rule="capacity",
                    )


def allowed_spread(rules: ScaleRules, division_kg: Decimal | None) -> Decimal:
    """The largest accepted spread: the setting, but never less than one division of the scale."""
    return max(rules.max_spread_kg, division_kg or Decimal(0))


def check_settled(
    sets: Sequence[tuple[str, WheelReadings]], *, rules: ScaleRules, division_kg: Decimal | None = None
) -> None:
    """Refuse repeated readings of one wheel that spread more than allowed: the scale had not settled."""
    allowed = allowed_spread(rules, division_kg)
    for prefix, readings in sets:
        for wheel in WHEELS:
            values = [v for v in readings.values(wheel) if v.is_finite()]
            if len(values) < 2:
                continue
            spread = max(values) - min(values)
            if spread > allowed:
                field = f"{prefix}.{wheel}"
                raise InvalidInput(
                    f"{field}: the repeated readings of {WHEEL_NAMES[wheel]} range from {_kg(min(values))} "
                    f"to {_kg(max(values))} kg, a spread of {_kg(spread)} kg, more than the allowed "
                    f"{_kg(allowed)} kg: the scale had not settled; weigh {WHEEL_NAMES[wheel]} again",
                    field=field,
                    rule="spread",
                )
