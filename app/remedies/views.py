"""The inspection page's "What would make it comply": a small GET form, the sentence, a table, the chart."""

from __future__ import annotations

from dataclasses import dataclass
from decimal import Decimal
from fractions import Fraction
from typing import Any

from starlette.datastructures import QueryParams

from app.config import get_settings
from app.dynamics.estimates import inspection_dynamics
from app.dynamics.wording import figure_text
from app.i18n.active import N_
from app.i18n.active import gettext as _
from app.inspections.models import Inspection
from app.remedies.service import stored_assessment
from app.stability import StabilityError
from app.stability.dynamics import rollover_after_remedy
from app.stability.remedies import Remedies, advice_of, complies, size_remedies
from app.web.chart import ChartPoint, before_after_chart, short_label
from app.web.forms import FormErrors, parse_decimal, query_text, readable
from app.web.refusals import translated_refusal
from app.wording import case_name, remedies_sentence, remedy_applied

REMEDIES = {"ballast": N_("Fitting front ballast"), "seat_shift": N_("Moving the rear bench forward")}
FIELDS = ("target_occupants", "ballast_x_m", "remedy")
INPUT_IDS = {"target_occupants": "target_occupants", "ballast_x_m": "ballast_x_m", "remedy": "remedy-ballast"}


@dataclass(frozen=True)
class RemedyChoice:
    """What the officer asked for: a target occupancy (None: every seat), a ballast position, a remedy."""

    target_occupants: int | None
    ballast_x_m: Decimal
    remedy: str


def read_choice(query: QueryParams, seats: int, errors: FormErrors) -> tuple[RemedyChoice, dict[str, str]]:
    """The form's values as typed and what they ask for; a bad value is named beside its field."""
    values = {name: query_text(query.get(name, ""), INPUT_IDS[name], errors, limit=20) for name in FIELDS}
    target: int | None = None
    if values["target_occupants"]:
        typed = values["target_occupants"]
        if typed.isascii() and typed.isdigit() and int(typed) <= seats:
            target = int(typed)
        else:
            errors.add(
                "target_occupants",
                _("Enter the number of occupants as a whole number from 0 to %(seats)s") % {"seats": seats},
            )
    ballast_x_m = get_settings().ballast_x_m
    if values["ballast_x_m"]:
        parsed = parse_decimal(values["ballast_x_m"])
        if parsed is None:
            errors.add(
                "ballast_x_m",
                _(
                    "Enter the ballast position in metres behind the front wheel centre, like %(example)s "
                    "(negative: ahead of it)"
                )
                % {"example": "0.30"},
            )
        else:
            ballast_x_m = parsed
    remedy = values["remedy"] or "ballast"
    if remedy not in REMEDIES:
        errors.add("remedy-ballast", _("Choose fitting front ballast or moving the rear bench forward"))
        remedy = "ballast"
    values["remedy"] = remedy
    return RemedyChoice(target, ballast_x_m, remedy), values


def _sized(inspection: Inspection, choice: RemedyChoice, errors: FormErrors) -> Remedies:
    """The remedies for the choice; a position the core refuses is named, and the default used instead."""
    assessment = stored_assessment(inspection)
    rules = get_settings().rules()
    try:
        return size_remedies(
            assessment, target_occupants=choice.target_occupants, ballast_x_m=choice.ballast_x_m, rules=rules
        )
    except StabilityError as error:
        errors.add(error.field, translated_refusal(readable(error.message)))
        return size_remedies(
            assessment,
            target_occupants=choice.target_occupants,
            ballast_x_m=get_settings().ballast_x_m,
            rules=rules,
        )


def _points(remedies: Remedies, after: list[Fraction | None]) -> list[ChartPoint]:
    return [
        ChartPoint(
            short_label(c.occupants), case_name(c.occupants), float(lsf), complies(lsf, remedies.layout)
        )
        for c, lsf in zip(remedies.cases, after, strict=True)
        if lsf is not None
    ]


def _rollover(threshold: float | None, lsf: Fraction, after: Fraction | None) -> str:
    """A rollover threshold as the estimates section writes it; a dash where the remedy does not apply."""
    if threshold is None or after is None:
        return "–"
    return figure_text(
        rollover_after_remedy(threshold, lsf_before=float(lsf), lsf_after=float(after)), 4, "g"
    )


def remedies_context(inspection: Inspection, query: QueryParams) -> tuple[dict[str, Any], FormErrors]:
    """The section's context (sentence, rows, chart, form values) and the form's errors."""
    errors = FormErrors()
    seats = len(inspection.loading_cases) - 1
    choice, values = read_choice(query, seats, errors)
    remedies = _sized(inspection, choice, errors)
    advice = advice_of(remedies)
    if not values["target_occupants"]:
        values["target_occupants"] = str(remedies.target_occupants)
    if not values["ballast_x_m"]:
        values["ballast_x_m"] = f"{get_settings().ballast_x_m}"
    chosen = [
        c.lsf_after_ballast if choice.remedy == "ballast" else c.lsf_after_seat_shift for c in remedies.cases
    ]
    applied = remedy_applied(advice, choice.remedy, remedies.layout)
    before = _points(remedies, [c.lsf for c in remedies.cases])
    chart = None
    if applied is not None and None not in chosen:
        chart = before_after_chart(
            before, _points(remedies, chosen), remedy=applied, limit=remedies.layout.limit
        )
    _inputs, estimates = inspection_dynamics(inspection)
    thresholds: dict[int, float | None] = {
        case.occupants: case.rollover_threshold_g for case in estimates.cases
    }
    thresholds = {c.occupants: thresholds.get(c.occupants) for c in remedies.cases}
    rows = [
        {
            "label": case_name(c.occupants),
            "rollover": _rollover(thresholds.get(c.occupants), c.lsf, c.lsf),
            "rollover_after_ballast": _rollover(thresholds.get(c.occupants), c.lsf, c.lsf_after_ballast),
            "rollover_after_seat_shift": _rollover(
                thresholds.get(c.occupants), c.lsf, c.lsf_after_seat_shift
            ),
            "lsf": c.lsf,
            "compliant": c.compliant,
            "after_ballast": c.lsf_after_ballast,
            "ballast_complies": bool(c.complies_after_ballast),
            "after_seat_shift": c.lsf_after_seat_shift,
            "seat_shift_complies": bool(c.complies_after_seat_shift),
        }
        for c in remedies.cases
    ]
    context = {
        "sentence": remedies_sentence(advice, remedies.layout),
        "layout_name": remedies.layout.name,
        "advice": advice,
        "rows": rows,
        "rollover_known": any(value is not None for value in thresholds.values()),
        "chart": chart,
        "limit": float(remedies.layout.limit),
        "limit_text": remedies.layout.limit_text,
        "applied": applied,
        "remedy_name": _(REMEDIES[choice.remedy]),
        "form": values,
        "remedies": {key: _(name) for key, name in REMEDIES.items()},
        "seats": seats,
    }
    return context, errors
