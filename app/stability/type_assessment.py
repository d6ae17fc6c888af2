"""Type (model-level) assessment: several vehicles of one model, their mean Table 4, spread and 95 % bound.

The type's Table 4 is the study's method: the mean of each wheel's reading and of the overall weight
over the vehicles, assessed like one vehicle (the ratio of the means). The confident verdict asks more:
per loading case the one-sided 95 % upper confidence bound of the vehicles' own LSF,
`mean + t(0.95, n-1) s / sqrt(n)`, must lie below 2/3, so a type passes only when its sample shows it.
"""

from __future__ import annotations

import decimal
from collections.abc import Sequence
from dataclasses import dataclass
from decimal import Decimal
from fractions import Fraction

from app.stability.errors import StabilityError
from app.stability.lsf import assess, assess_averaged
from app.stability.model import LSF_LIMIT, Assessment, AssessmentInput, AveragedReadings, Rules

FIELD = "inspection_ids"

# One-sided 95 % quantiles of Student's t, t(0.95, df), rounded UP at the 9th decimal so a bound
# computed from them is never below the true one. For df beyond the table the value of the largest
# tabled df not above it is used: t falls as df grows, so that only widens the bound (conservative).
T_95: dict[int, Decimal] = {
    df: Decimal(text)
    for df, text in {
        1: "6.313751515", 2: "2.919985581", 3: "2.353363435", 4: "2.131846787", 5: "2.015048374",
        6: "1.943180281", 7: "1.894578606", 8: "1.859548038", 9: "1.833112933", 10: "1.812461123",
        11: "1.795884819", 12: "1.782287556", 13: "1.770933396", 14: "1.761310136", 15: "1.753050356",
        16: "1.745883677", 17: "1.739606727", 18: "1.734063607", 19: "1.729132812", 20: "1.724718243",
        21: "1.720742903", 22: "1.717144375", 23: "1.713871528", 24: "1.710882080", 25: "1.708140762",
        26: "1.705617920", 27: "1.703288446", 28: "1.701130935", 29: "1.699127027", 30: "1.697260887",
        31: "1.695518783", 32: "1.693888749", 33: "1.692360310", 34: "1.690924256", 35: "1.689572458",
        36: "1.688297715", 37: "1.687093620", 38: "1.685954461", 39: "1.684875122", 40: "1.683851014",
        41: "1.682878003", 42: "1.681952358", 43: "1.681070704", 44: "1.680229977", 45: "1.679427393",
        46: "1.678660414", 47: "1.677926722", 48: "1.677224197", 49: "1.676550893", 50: "1.675905026",
        51: "1.675284951", 52: "1.674689154", 53: "1.674116237", 54: "1.673564907", 55: "1.673033966",
        56: "1.672522304", 57: "1.672028889", 58: "1.671552763", 59: "1.671093033", 60: "1.670648865",
        80: "1.664124579", 100: "1.660234327", 120: "1.657650900", 200: "1.652508101", 500: "1.647906854",
        1000: "1.646378818",
    }.items()
}  # fmt: skip


def t_95(df: int) -> Decimal:
    """Student's t(0.95, df) from the table; beyond it, the largest tabled df not above `df`."""
    if df < 1:
        raise ValueError("Student's t needs at least one degree of freedom (two vehicles)")
    return T_95[max(d for d in T_95 if d <= df)]


@dataclass(frozen=True)
class Member:
    """One vehicle's inspection in a type assessment, with the rules it was assessed under."""

    label: str  # the registration number, for messages
    data: AssessmentInput
    rules: Rules


@dataclass(frozen=True)
class CaseSpread:
    """One loading case across the vehicles: their LSF's min, mean, max, spread and 95 % upper bound."""

    occupants: int
    lsfs: tuple[Fraction, ...]
    t: Decimal
    limit: Fraction = LSF_LIMIT  # the layout's (2/3 for the delta)

    @property
    def n(self) -> int:
        """How many vehicles."""
        return len(self.lsfs)

    @property
    def min_lsf(self) -> Fraction:
        """The smallest vehicle LSF."""
        return min(self.lsfs)

    @property
    def max_lsf(self) -> Fraction:
        """The largest vehicle LSF."""
        return max(self.lsfs)

    @property
    def mean_lsf(self) -> Fraction:
        """The mean of the vehicles' LSF (not the type's ratio of means)."""
        return sum(self.lsfs, Fraction(0)) / self.n

    @property
    def sample_variance(self) -> Fraction:
        """s squared, with n - 1 in the denominator, exact."""
        mean = self.mean_lsf
        return sum(((x - mean) ** 2 for x in self.lsfs), Fraction(0)) / (self.n - 1)

    @property
    def sd_lsf(self) -> Decimal:
        """The sample standard deviation s (irrational in general: 28 significant digits)."""
        return _sqrt(self.sample_variance)

    @property
    def upper_95_lsf(self) -> Decimal:
        """mean + t s / sqrt(n), to 28 significant digits; the verdict uses the exact comparison."""
        with decimal.localcontext() as context:
            context.prec = 28
            return _decimal(self.mean_lsf) + self.t * _sqrt(self.sample_variance / self.n)

    @property
    def confident_compliant(self) -> bool:
        """The upper bound is below the limit (2/3), decided exactly: t s / sqrt(n) < limit - mean."""
        margin = self.limit - self.mean_lsf
        if margin <= 0:
            return False
        return Fraction(self.t) ** 2 * self.sample_variance / self.n < margin**2


@dataclass(frozen=True)
class TypeAssessment:
    """The outcome of a type assessment: each vehicle's own, the type's Table 4 and the spread."""

    members: tuple[Member, ...]
    vehicles: tuple[Assessment, ...]
    table: Assessment  # the type's Table 4 from the mean readings
    spread: tuple[CaseSpread, ...]

    @property
    def compliant(self) -> bool:
        """The type complies only when every case complies with confidence."""
        return all(case.confident_compliant for case in self.spread)

    @property
    def max_compliant_occupants(self) -> int:
        """Largest k such that the cases with 1..k occupants comply with confidence; else 0."""
        best = 0
        for case in self.spread:
            if case.occupants == 0:
                continue
            if not case.confident_compliant:
                break
            best = case.occupants
        return best


def assess_type(members: Sequence[Member]) -> TypeAssessment:
    """Assess two or more vehicles of one model with one seat layout and occupant mass."""
    if len(members) < 2:
        raise StabilityError(
            FIELD, "too_few", f"{FIELD}: a type assessment needs the inspections of at least two vehicles"
        )
    _check_one_layout(members)
    vehicles = tuple(assess(m.data, m.rules) for m in members)
    first = members[0]
    mean_data = AssessmentInput(
        readings=first.data.readings,  # unused: the mean readings below stand in for them
        wheelbase_m=first.data.wheelbase_m,
        seats=first.data.seats,
        load_items=first.data.load_items,
        occupant_mass_kg=vehicles[0].occupant_mass_kg,
        layout=first.data.layout,
    )
    table = assess_averaged(_mean_readings(vehicles), mean_data, first.rules)
    t = t_95(len(members) - 1)
    spread = tuple(
        CaseSpread(case.occupants, tuple(v.cases[index].lsf for v in vehicles), t, table.layout.limit)
        for index, case in enumerate(table.cases)
    )
    return TypeAssessment(members=tuple(members), vehicles=vehicles, table=table, spread=spread)


def _mean_readings(vehicles: Sequence[Assessment]) -> AveragedReadings:
    """The mean of each wheel's averaged reading and of each vehicle's weight (overall, else the sum)."""
    n = len(vehicles)
    layout = vehicles[0].layout
    return AveragedReadings(
        means={w: sum((v.readings.mean(w) for v in vehicles), Fraction(0)) / n for w in layout.wheels},
        overall_kg=sum((v.readings.total_kg for v in vehicles), Fraction(0)) / n,
        layout=layout,
    )


def _check_one_layout(members: Sequence[Member]) -> None:
    """Refuse vehicles whose seats, wheelbase, load items or occupant mass differ, naming them."""
    first = members[0]
    for member in members:
        if member.data.measured_cases:
            raise StabilityError(
                FIELD,
                "measured_cases",
                f"{FIELD}: the inspection of {member.label} has loading cases weighed directly; a type "
                "assessment averages the empty-vehicle readings, so choose an inspection without them",
            )
    facts = (
        ("axle layout", lambda m: m.data.layout.name),
        ("seat layout", lambda m: m.data.seats),
        ("wheelbase", lambda m: m.data.wheelbase_m),
        ("load items", lambda m: tuple((i.mass_kg, i.x_m) for i in m.data.load_items)),
        ("occupant mass", lambda m: _mass(m)),
    )
    for what, fact in facts:
        for member in members[1:]:
            if fact(member) != fact(first):
                raise StabilityError(
                    FIELD,
                    "same_layout",
                    f"{FIELD}: {first.label} and {member.label} differ in {what}; a type assessment "
                    "needs vehicles with one seat layout, wheelbase, load items and occupant mass",
                )


def _mass(member: Member) -> Decimal:
    mass = member.data.occupant_mass_kg
    return mass if mass is not None else member.rules.occupant_mass_kg


def _decimal(value: Fraction) -> Decimal:
    return Decimal(value.numerator) / Decimal(value.denominator)


def _sqrt(value: Fraction) -> Decimal:
    with decimal.localcontext() as context:
        context.prec = 28
        return _decimal(value).sqrt()
