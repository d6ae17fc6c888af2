"""Sized remedies for a non-compliant vehicle: front ballast, passenger seats forward, stiffer rear tyres.

Reference section 6. For a case with total W and rear load R (kg), non-compliant when 3R >= 2W:
ballast m_b at x_b complies when m_b > (3R - 2W) / (2 - 3 x_b / WB) (x_b < 2/3 WB); moving every
passenger seat forward by d complies when d > (3R - 2W) WB / (3 p m_o) (p >= 1 passengers); rear tyres
understeer when CaR / CaF > R / (2 (W - R)). Decided in exact fractions; the advice is rounded up.

Section 9 for any layout of n_f front and n_r rear tyres (the delta: 1 and 2, giving the above): the
excess is (n_f + n_r) R - n_r W, ballast needs m_b > excess / (n_r - (n_f + n_r) x_b / WB), the seats
d > excess WB / ((n_f + n_r) p m_o), the rear tyres CaR / CaF > n_f R / (n_r F).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from decimal import Decimal
from fractions import Fraction

from app.stability.errors import StabilityError
from app.stability.layout import DELTA, Layout
from app.stability.model import Assessment, LoadingCase, Rules
from app.stability.validation import check_position

# Every advised figure is the least multiple of its step strictly above the exact bound: it suffices.
BALLAST_STEP = Fraction(1, 100)  # kg
SHIFT_STEP = Fraction(1, 1000)  # m
RATIO_STEP = Fraction(1, 1000)


def advice(bound: Fraction, step: Fraction) -> Fraction:
    """The least multiple of `step` strictly greater than `bound` (at an exact multiple, the next one)."""
    return (math.floor(bound / step) + 1) * step


def as_decimal(value: Fraction, step: Fraction) -> Decimal:
    """An advised figure (a multiple of `step`) as a Decimal with the step's places: 54.64, 0.262."""
    places = len(str(step.denominator)) - 1
    return (Decimal(value.numerator) / Decimal(value.denominator)).quantize(Decimal(1).scaleb(-places))


@dataclass(frozen=True)
class CaseRemedies:
    """One loading case: its excess, what each remedy needs for it alone, and its LSF after each."""

    occupants: int
    lsf: Fraction
    compliant: bool
    excess_kg: Fraction  # 3R - 2W: positive (or zero) when the case does not comply
    ballast_kg: Fraction | None  # exact bound; None when the case complies or ballast cannot mend it
    seat_shift_m: Fraction | None  # exact bound; None when the case complies or has no passenger
    tyre_ratio: Fraction  # R / (2 (W - R)): the rear tyres must exceed the front's stiffness by this
    lsf_after_ballast: Fraction | None  # with the advised ballast fitted (None: no ballast advised)
    lsf_after_seat_shift: Fraction | None  # with the seats moved by the advised distance
    layout: Layout = DELTA  # whose limit decides the verdicts after a remedy

    @property
    def complies_after_ballast(self) -> bool | None:
        """The verdict with the advised ballast fitted (None: none advised), under the layout's limit."""
        return None if self.lsf_after_ballast is None else complies(self.lsf_after_ballast, self.layout)

    @property
    def complies_after_seat_shift(self) -> bool | None:
        """The verdict with the seats moved (None: not advised), under the layout's limit."""
        return None if self.lsf_after_seat_shift is None else complies(self.lsf_after_seat_shift, self.layout)

    @property
    def fixable_by_ballast(self) -> bool:
        """True when the case complies or some ballast at the chosen position mends it."""
        return self.compliant or self.ballast_kg is not None

    @property
    def fixable_by_seat_shift(self) -> bool:
        """True when the case complies or moving the passenger seats forward mends it."""
        return self.compliant or self.seat_shift_m is not None


@dataclass(frozen=True)
class Remedy:
    """One remedy over every case up to the target: the exact bound, the advice and the binding case."""

    bound: Fraction | None  # the largest of the cases' bounds (strictly more than it is needed)
    advised: Fraction | None  # the bound rounded up to the next step above it
    binding_occupants: int | None  # the case that needs the most
    unfixable_occupants: tuple[int, ...] = ()

    @property
    def possible(self) -> bool:
        """True when every non-compliant case up to the target can be mended this way."""
        return not self.unfixable_occupants


@dataclass(frozen=True)
class Remedies:
    """What would make every loading case up to `target_occupants` comply (None: nothing is needed)."""

    target_occupants: int
    compliant: bool  # every case up to the target already complies
    max_compliant_occupants: int
    ballast_x_m: Decimal
    ballast: Remedy | None
    seat_shift: Remedy | None
    rear_tyre_ratio: Remedy | None
    cases: tuple[CaseRemedies, ...]
    layout: Layout = DELTA


def excess(case: LoadingCase) -> Fraction:
    """(n_f + n_r) R - n_r W (3R - 2W on a delta): how far the case is from complying; < 0 when it does."""
    layout = case.layout
    return (layout.n_front + layout.n_rear) * case.rear_kg - layout.n_rear * case.total_kg


def ballast_bound(case: LoadingCase, x_m: Fraction, wheelbase_m: Fraction) -> Fraction | None:
    """The ballast mass (kg) at `x_m` the case needs strictly more than; None if no mass can mend it."""
    layout = case.layout
    denominator = layout.n_rear - (layout.n_front + layout.n_rear) * x_m / wheelbase_m
    if denominator <= 0:  # at or behind limit * WB the ballast's own share of the rear is the limit or more
        return None
    return max(excess(case), Fraction(0)) / denominator


def seat_shift_bound(case: LoadingCase, occupant_mass_kg: Fraction, wheelbase_m: Fraction) -> Fraction | None:
    """How far (m) every passenger seat must move forward, strictly more than; None without passengers."""
    passengers = case.occupants - 1  # the driver's seat is always the first and stays
    if passengers < 1:
        return None
    tyres = case.layout.n_front + case.layout.n_rear
    return max(excess(case), Fraction(0)) * wheelbase_m / (tyres * passengers * occupant_mass_kg)


def tyre_ratio(case: LoadingCase) -> Fraction:
    """CaR / CaF at which the case is just stable: n_f R / (n_r F) (R / 2F on a delta); 1 at the limit."""
    return case.layout.n_front * case.rear_kg / (case.layout.n_rear * case.front_kg)


def lsf_with_ballast(case: LoadingCase, mass_kg: Fraction, x_m: Fraction, wheelbase_m: Fraction) -> Fraction:
    """The case's LSF with `mass_kg` fitted `x_m` behind the front wheel centre."""
    return (case.rear_kg + mass_kg * x_m / wheelbase_m) / (case.total_kg + mass_kg)


def lsf_with_seat_shift(
    case: LoadingCase, shift_m: Fraction, occupant_mass_kg: Fraction, wheelbase_m: Fraction
) -> Fraction:
    """The case's LSF with every passenger seat `shift_m` further forward."""
    passengers = max(case.occupants - 1, 0)
    return (case.rear_kg - passengers * occupant_mass_kg * shift_m / wheelbase_m) / case.total_kg


def check_target(assessment: Assessment, target_occupants: int) -> None:
    """Refuse a target occupancy below zero or above the number of seats."""
    seats = assessment.cases[-1].occupants
    if not 0 <= target_occupants <= seats:
        raise StabilityError(
            "target_occupants",
            "range",
            f"target_occupants: the vehicle has {seats} seat(s); choose from 0 to {seats} occupants, "
            f"got {target_occupants}",
        )


def _remedy(bounds: dict[int, Fraction | None], cases: list[LoadingCase], step: Fraction) -> Remedy | None:
    """The largest bound over the non-compliant cases, the case it comes from, and the unmendable ones."""
    failing = [case.occupants for case in cases if not case.compliant]
    if not failing:
        return None
    unfixable = tuple(n for n in failing if bounds[n] is None)
    known = {n: bound for n in failing if (bound := bounds[n]) is not None}
    if not known:
        return Remedy(None, None, None, unfixable)
    binding = max(known, key=lambda n: (known[n], n))
    return Remedy(known[binding], advice(known[binding], step), binding, unfixable)


def size_remedies(
    assessment: Assessment,
    *,
    target_occupants: int | None = None,
    ballast_x_m: Decimal = Decimal("0.30"),
    rules: Rules | None = None,
) -> Remedies:
    """Size each remedy for every loading case up to the target (None: every seat filled), exactly."""
    rules = rules or Rules()
    target = assessment.cases[-1].occupants if target_occupants is None else target_occupants
    check_target(assessment, target)
    check_position(ballast_x_m, assessment.wheelbase_m, rules, field="ballast_x_m")
    wheelbase = Fraction(assessment.wheelbase_m)
    x_b = Fraction(ballast_x_m)
    mass = Fraction(assessment.occupant_mass_kg)
    cases = [case for case in assessment.cases if case.occupants <= target]

    ballast = _remedy({c.occupants: ballast_bound(c, x_b, wheelbase) for c in cases}, cases, BALLAST_STEP)
    shift = _remedy({c.occupants: seat_shift_bound(c, mass, wheelbase) for c in cases}, cases, SHIFT_STEP)
    tyres = _remedy({c.occupants: tyre_ratio(c) for c in cases}, cases, RATIO_STEP)
    fit = ballast.advised if ballast else None
    moved = shift.advised if shift else None
    rows = tuple(
        CaseRemedies(
            occupants=case.occupants,
            lsf=case.lsf,
            compliant=case.compliant,
            excess_kg=excess(case),
            ballast_kg=None if case.compliant else ballast_bound(case, x_b, wheelbase),
            seat_shift_m=None if case.compliant else seat_shift_bound(case, mass, wheelbase),
            tyre_ratio=tyre_ratio(case),
            lsf_after_ballast=None if fit is None else lsf_with_ballast(case, fit, x_b, wheelbase),
            lsf_after_seat_shift=None if moved is None else lsf_with_seat_shift(case, moved, mass, wheelbase),
            layout=case.layout,
        )
        for case in cases
    )
    return Remedies(
        target_occupants=target,
        compliant=all(case.compliant for case in cases),
        max_compliant_occupants=assessment.max_compliant_occupants,
        ballast_x_m=ballast_x_m,
        ballast=ballast,
        seat_shift=shift,
        rear_tyre_ratio=tyres,
        cases=rows,
        layout=assessment.layout,
    )


def complies(lsf: Fraction, layout: Layout = DELTA) -> bool:
    """The verdict on an LSF after a remedy: strictly below the layout's limit (2/3 on a delta)."""
    return lsf < layout.limit


@dataclass(frozen=True)
class Advice:
    """The advised figures of sized remedies, as a document prints and keeps them (None: not advised)."""

    target_occupants: int
    compliant: bool
    max_compliant_occupants: int
    ballast_x_m: Decimal
    ballast_kg: Decimal | None  # None with ballast_possible False: ballast there cannot help
    ballast_possible: bool
    seat_shift_m: Decimal | None  # None: no case with passengers needs it, or none can be mended
    seat_shift_unfixable: tuple[int, ...]
    tyre_ratio: Decimal | None


def advice_of(remedies: Remedies) -> Advice:
    """The advised figures of sized remedies: each the least step above its exact bound."""
    ballast, shift, tyres = remedies.ballast, remedies.seat_shift, remedies.rear_tyre_ratio
    return Advice(
        target_occupants=remedies.target_occupants,
        compliant=remedies.compliant,
        max_compliant_occupants=remedies.max_compliant_occupants,
        ballast_x_m=remedies.ballast_x_m,
        ballast_kg=as_decimal(ballast.advised, BALLAST_STEP) if ballast and ballast.advised else None,
        ballast_possible=ballast is None or ballast.possible,
        seat_shift_m=as_decimal(shift.advised, SHIFT_STEP) if shift and shift.advised else None,
        seat_shift_unfixable=shift.unfixable_occupants if shift else (),
        tyre_ratio=as_decimal(tyres.advised, RATIO_STEP) if tyres and tyres.advised else None,
    )
