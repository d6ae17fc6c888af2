"""Axle layouts: which wheels a vehicle stands on, the limit they give and the words for them.

Reference section 9: with `n_f` front and `n_r` rear tyres, all alike, the vehicle understeers when
each rear tyre carries less than each front tyre, `R / n_r < F / n_f`, that is `LSF < n_r / (n_f + n_r)`.
Every door reads a vehicle's truth from its `Layout`, never from its name.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Literal

from app.stability.errors import StabilityError

LayoutName = Literal["delta", "tadpole", "quadricycle"]

# Every wheel any layout has, in the order a weighing goes round the vehicle, then the overall weight.
ALL_WHEELS: tuple[str, ...] = (
    "front_kg",
    "left_front_kg",
    "right_front_kg",
    "left_rear_kg",
    "right_rear_kg",
    "rear_kg",
)
OVERALL = "overall_kg"

WHEEL_WORDS: dict[str, str] = {
    "front_kg": "front wheel reaction",
    "left_front_kg": "left front wheel reaction",
    "right_front_kg": "right front wheel reaction",
    "left_rear_kg": "left rear wheel reaction",
    "right_rear_kg": "right rear wheel reaction",
    "rear_kg": "rear wheel reaction",
    "overall_kg": "overall weight",
}


@dataclass(frozen=True)
class Layout:
    """An axle layout: its wheels front and rear (each a reading), the limit they give, its words."""

    name: LayoutName
    front_wheels: tuple[str, ...]
    rear_wheels: tuple[str, ...]
    description: str  # "one front wheel and two rear wheels"

    @property
    def n_front(self) -> int:
        """Tyres on the front axle."""
        return len(self.front_wheels)

    @property
    def n_rear(self) -> int:
        """Tyres on the rear axle."""
        return len(self.rear_wheels)

    @property
    def limit(self) -> Fraction:
        """The exact limit of the LSF, n_r / (n_f + n_r): 2/3, 1/3 or 1/2; exactly at it is NC."""
        return Fraction(self.n_rear, self.n_front + self.n_rear)

    @property
    def wheels(self) -> tuple[str, ...]:
        """Every wheel to read, front first, in the order a weighing goes round the vehicle."""
        return self.front_wheels + self.rear_wheels

    @property
    def limit_text(self) -> str:
        """The limit as a fraction, "2/3"."""
        return f"{self.limit.numerator}/{self.limit.denominator}"

    @property
    def rear_axle_words(self) -> str:
        """ "rear wheel" or "rear wheels", as the vehicle has."""
        return "rear wheel" if self.n_rear == 1 else "rear wheels"

    @property
    def front_axle_words(self) -> str:
        """ "front wheel" or "front wheels", as the vehicle has."""
        return "front wheel" if self.n_front == 1 else "front wheels"

    @property
    def title(self) -> str:
        """The layout for a person: "Tadpole (two front wheels and one rear wheel)"."""
        return f"{self.name.capitalize()} ({self.description})"


DELTA = Layout(
    "delta", ("front_kg",), ("left_rear_kg", "right_rear_kg"), "one front wheel and two rear wheels"
)
TADPOLE = Layout(
    "tadpole", ("left_front_kg", "right_front_kg"), ("rear_kg",), "two front wheels and one rear wheel"
)
QUADRICYCLE = Layout(
    "quadricycle",
    ("left_front_kg", "right_front_kg"),
    ("left_rear_kg", "right_rear_kg"),
    "two front wheels and two rear wheels",
)
LAYOUTS: dict[str, Layout] = {layout.name: layout for layout in (DELTA, TADPOLE, QUADRICYCLE)}
LAYOUT_NAMES: tuple[LayoutName, ...] = ("delta", "tadpole", "quadricycle")


def layout_named(name: str, *, field: str = "layout") -> Layout:
    """The layout of this name; refuse one that does not exist, naming the field and the choices."""
    try:
        return LAYOUTS[name]
    except (KeyError, TypeError):
        raise StabilityError(
            field,
            "unknown_layout",
            f"{field}: {name!r} is not an axle layout; choose one of {', '.join(LAYOUT_NAMES)}",
        ) from None
