"""Beyond the static test: CG height by axle lift, rollover threshold, critical speed, LSF at speed.

Estimates from assumed inputs (reference sections 4 and 5), in floats: square roots and arctangents.
They never touch the static verdict, which stays exact in `lsf.py`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from app.stability.errors import StabilityError

# Standard gravity turns kilograms into newtons. The reference's 33.6 km/h uses 9.81; both give 33.6.
G = 9.80665
KMH_PER_MS = 3.6
DEFAULT_AIR_DENSITY = 1.2  # kg/m^3
LSF_LIMIT = 2 / 3  # the estimates compare in floats; the verdict's exact 2/3 is in model.py

# Plausibility bounds (exclusive minimum, inclusive maximum) of each input, named like its field.
SEAT_HEIGHT_M = (0.2, 2.0)  # a seated person's CG above the ground
BOUNDS: dict[str, tuple[float, float, str]] = {
    "track_m": (0.0, 3.0, "rear track"),
    "front_track_m": (0.0, 3.0, "front track"),
    "wheel_radius_m": (0.0, 1.0, "loaded rear wheel radius"),
    "cg_height_m": (0.0, 3.0, "centre of gravity height"),
    "cg_lift.lift_height_m": (0.0, 2.0, "height the front axle is raised"),
    "cg_lift.front_kg": (0.0, 1500.0, "front wheel(s) reaction with the front axle raised"),
    "front_cornering_stiffness_n_per_rad": (0.0, 1e6, "front tyre cornering stiffness"),
    "rear_cornering_stiffness_n_per_rad": (0.0, 1e6, "rear tyre cornering stiffness"),
    "drag_area_m2": (0.0, 20.0, "drag area (Cd x A)"),
    "centre_of_pressure_height_m": (0.0, 3.0, "centre of pressure height"),
    "air_density_kg_m3": (0.0, 2.0, "air density"),
}
SPEED_KMH = (0.0, 200.0)
ACCELERATION_MS2 = (-10.0, 10.0)


@dataclass(frozen=True)
class CaseLoad:
    """One loading case as the static core decided it: occupants, total and rear load (kg)."""

    occupants: int
    total_kg: float
    rear_kg: float
    compliant: bool | None = None  # the exact static verdict, when known: floats never overrule it

    @property
    def lsf(self) -> float:
        """Share of the weight on the rear wheels."""
        return self.rear_kg / self.total_kg


@dataclass(frozen=True)
class VehicleDynamics:
    """The vehicle's assumed or measured figures beyond the weighing; None where unknown."""

    track_m: float | None = None  # the rear track: two rear wheels (delta, quadricycle)
    wheel_radius_m: float | None = None
    seat_heights_m: tuple[float | None, ...] = ()  # z of each seat, driver first
    front_cornering_stiffness_n_per_rad: float | None = None
    rear_cornering_stiffness_n_per_rad: float | None = None
    drag_area_m2: float | None = None
    centre_of_pressure_height_m: float | None = None
    front_track_m: float | None = None  # two front wheels (tadpole, quadricycle)


@dataclass(frozen=True)
class AxleLift:
    """A second weighing with the front axle raised by `lift_height_m`; `front_kg` (both front wheels
    together on a tadpole or quadricycle) read again."""

    lift_height_m: float
    front_kg: float


@dataclass(frozen=True)
class DynamicsInput:
    """Everything the estimates may use; the empty case first, then one case per occupant added."""

    wheelbase_m: float
    front_level_kg: float  # F_0, the empty weighing's front reaction
    cases: tuple[CaseLoad, ...]
    vehicle: VehicleDynamics
    cg_lift: AxleLift | None = None
    cg_height_m: float | None = None  # given directly instead of the lift
    has_load_items: bool = False  # their heights are unknown: no case CG height then
    weighed_total_kg: float | None = None  # the weighing's W when load items make case 0 heavier
    # The axle layout's tyres (reference section 9): the delta's one front and two rear by default.
    n_front: int = 1
    n_rear: int = 2

    @property
    def limit(self) -> float:
        """The layout's LSF limit n_r / (n_f + n_r) as a float, for the estimates only (2/3 on a delta)."""
        return self.n_rear / (self.n_front + self.n_rear)


@dataclass(frozen=True)
class CaseDynamics:
    """The estimates of one loading case; each None when an input it needs is unknown."""

    occupants: int
    cg_height_m: float | None
    rollover_threshold_g: float | None
    tilt_angle_deg: float | None
    understeer_margin_nm_per_rad: float | None
    critical_speed_ms: float | None

    @property
    def critical_speed_kmh(self) -> float | None:
        """The critical speed in km/h."""
        return None if self.critical_speed_ms is None else self.critical_speed_ms * KMH_PER_MS


@dataclass(frozen=True)
class Dynamics:
    """The estimates of every case, the empty vehicle's CG height and the inputs that were missing."""

    empty_cg_height_m: float | None
    cases: tuple[CaseDynamics, ...]
    missing: tuple[str, ...]


@dataclass(frozen=True)
class CaseAtSpeed:
    """One case driven at a speed and acceleration: the LSF with the load moved rearward."""

    occupants: int
    lsf_at_speed: float | None
    compliant_at_speed: bool | None
    margin_speed_kmh: float | None  # drag alone uses up the static margin; None for a static NC


def check_value(value: float, field: str) -> float:
    """Refuse a non-finite or out-of-range input, naming the field and its bounds."""
    low, high, what = BOUNDS[field]
    if not math.isfinite(value):
        raise StabilityError(field, "finite", f"{field}: enter the {what} as a finite number")
    if not low < value <= high:
        rule = "positive" if value <= 0 else "range"
        raise StabilityError(
            field,
            rule,
            f"{field}: the {what} must be more than {_g(low)} and at most {_g(high)}; got {_g(value)}",
        )
    return value


def check_seat_height(value: float, field: str) -> float:
    """Refuse a seated CG height outside 0.2-2.0 m."""
    low, high = SEAT_HEIGHT_M
    if not math.isfinite(value) or not low <= value <= high:
        raise StabilityError(
            field,
            "range",
            f"{field}: a seated person's centre of gravity lies between {low} and {high} m above the "
            f"ground; got {_g(value)}",
        )
    return value


def check_speed(speed_kmh: float, acceleration_ms2: float) -> None:
    """Refuse a speed outside 0-200 km/h or an acceleration outside -10 to 10 m/s^2."""
    for field, value, (low, high), what in (
        ("speed_kmh", speed_kmh, SPEED_KMH, "speed must be between {} and {} km/h"),
        (
            "acceleration_ms2",
            acceleration_ms2,
            ACCELERATION_MS2,
            "acceleration must be between {} and {} m/s²",
        ),
    ):
        if not math.isfinite(value) or not low <= value <= high:
            rule = "finite" if not math.isfinite(value) else "range"
            raise StabilityError(field, rule, f"{field}: the {what.format(_g(low), _g(high))}; got {value}")


def check_vehicle(vehicle: VehicleDynamics) -> None:
    """Refuse any implausible figure of the vehicle's dynamics, naming the field."""
    for name in (
        "track_m",
        "front_track_m",
        "wheel_radius_m",
        "front_cornering_stiffness_n_per_rad",
        "rear_cornering_stiffness_n_per_rad",
        "drag_area_m2",
        "centre_of_pressure_height_m",
    ):
        value = getattr(vehicle, name)
        if value is not None:
            check_value(value, name)
    for index, z in enumerate(vehicle.seat_heights_m):
        if z is not None:
            check_seat_height(z, f"seats[{index}].z_m")


def check_axle_lift(lift: AxleLift, *, wheelbase_m: float, front_level_kg: float) -> None:
    """Refuse a lift of no height or as high as the wheelbase, or a raised reading not below the level one."""
    check_value(lift.lift_height_m, "cg_lift.lift_height_m")
    check_value(lift.front_kg, "cg_lift.front_kg")
    if lift.lift_height_m >= wheelbase_m:
        raise StabilityError(
            "cg_lift.lift_height_m",
            "below_wheelbase",
            f"cg_lift.lift_height_m: the front axle can be raised by less than the wheelbase "
            f"({_g(wheelbase_m)} m); got {_g(lift.lift_height_m)} m",
        )
    if lift.front_kg >= front_level_kg:
        raise StabilityError(
            "cg_lift.front_kg",
            "less_than_level",
            f"cg_lift.front_kg: with the front axle raised its wheel(s) must carry less than level "
            f"({_g(front_level_kg)} kg), since the CG lies above the wheel centres; "
            f"got {_g(lift.front_kg)} kg. Weigh the raised wheel(s) again",
        )


def cg_height_by_axle_lift(
    *,
    wheelbase_m: float,
    total_kg: float,
    front_level_kg: float,
    lift: AxleLift,
    wheel_radius_m: float,
) -> float:
    """The empty vehicle's CG height h = r + WB (F_0 - F_phi) / (W tan phi), sin phi = H / WB."""
    check_axle_lift(lift, wheelbase_m=wheelbase_m, front_level_kg=front_level_kg)
    check_value(wheel_radius_m, "wheel_radius_m")
    tan_phi = math.tan(math.asin(lift.lift_height_m / wheelbase_m))
    return wheel_radius_m + wheelbase_m * (front_level_kg - lift.front_kg) / (total_kg * tan_phi)


def check_given_cg_height(cg_height_m: float, wheel_radius_m: float | None) -> float:
    """Refuse a given CG height out of range or at or below the wheel centre."""
    check_value(cg_height_m, "cg_height_m")
    if wheel_radius_m is not None and cg_height_m <= wheel_radius_m:
        raise StabilityError(
            "cg_height_m",
            "above_wheel_centre",
            f"cg_height_m: a tricycle's centre of gravity lies above its wheel centres "
            f"({_g(wheel_radius_m)} m); got {_g(cg_height_m)} m",
        )
    return cg_height_m


def case_cg_height(
    *, empty_total_kg: float, empty_cg_height_m: float, occupant_kg: float, seat_heights_m: Sequence[float]
) -> float:
    """h_k = (W0 h0 + sum of m_o z_i over the seats filled) / W_k."""
    total = empty_total_kg + occupant_kg * len(seat_heights_m)
    return (empty_total_kg * empty_cg_height_m + occupant_kg * sum(seat_heights_m)) / total


def rollover_threshold(*, track_m: float, cg_height_m: float, lsf: float) -> float:
    """Static rollover threshold (T / 2h) LSF, in g."""
    return track_m / (2 * cg_height_m) * lsf


def rollover_threshold_about_axis(
    *, front_track_m: float, rear_track_m: float, cg_height_m: float, lsf: float
) -> float:
    """Any layout (reference section 9): the vehicle tips about the line from an outer front contact
    point to the outer rear one on the same side, which passes the CG's station L1 = LSF WB at
    y = T_f / 2 + (T_r / 2 - T_f / 2) LSF from the centre line; the threshold is y / h, in g.

    A single wheel has track 0: the delta's (T_r / 2h) LSF, the tadpole's (T_f / 2h) (1 - LSF), a
    quadricycle with equal tracks T / 2h.
    """
    if front_track_m == 0:  # one front wheel: the study's own expression, to the last bit
        return rollover_threshold(track_m=rear_track_m, cg_height_m=cg_height_m, lsf=lsf)
    return (front_track_m / 2 + (rear_track_m / 2 - front_track_m / 2) * lsf) / cg_height_m


def rollover_after_remedy(threshold_g: float, *, lsf_before: float, lsf_after: float) -> float:
    """A case's rollover threshold once a remedy has moved its LSF, its CG height kept: exact for
    seats moved forward (no height changes), and for ballast the figure when the ballast sits at the
    case's CG height (ballast mounted lower lowers the CG, so the threshold is then higher)."""
    return threshold_g * lsf_after / lsf_before


def tilt_angle_deg(threshold_g: float) -> float:
    """The tilt-table angle at which the case would tip, atan of its threshold, in degrees."""
    return math.degrees(math.atan(threshold_g))


def understeer_margin(
    *,
    wheelbase_m: float,
    lsf: float,
    front_n_per_rad: float,
    rear_n_per_rad: float,
    n_front: int = 1,
    n_rear: int = 2,
) -> float:
    """S = n_r L2 CaR - n_f L1 CaF (N m/rad), 2 L2 CaR - L1 CaF on a delta; positive understeers."""
    l1 = wheelbase_m * lsf
    l2 = wheelbase_m - l1
    return n_rear * l2 * rear_n_per_rad - n_front * l1 * front_n_per_rad


def critical_speed_ms(
    *,
    wheelbase_m: float,
    mass_kg: float,
    margin: float,
    front_n_per_rad: float,
    rear_n_per_rad: float,
    n_front: int = 1,
    n_rear: int = 2,
) -> float | None:
    """WB sqrt(n_f CaF n_r CaR / (m (n_f L1 CaF - n_r L2 CaR))) when S < 0 (the delta's
    WB sqrt(2 CaF CaR / (m (L1 CaF - 2 L2 CaR)))); None otherwise (no finite speed)."""
    if margin >= 0:  # S = 0 is neutral steer: the linear model has no finite critical speed
        return None
    return wheelbase_m * math.sqrt(n_front * n_rear * front_n_per_rad * rear_n_per_rad / (mass_kg * -margin))


def _tracks(data: DynamicsInput, missing: list[str]) -> tuple[float, float] | None:
    """The front and rear tracks of the tipping axis (0 for a single wheel); None, with the missing
    figures named, while an axle of two wheels has no track on record."""
    vehicle = data.vehicle
    front = 0.0 if data.n_front == 1 else vehicle.front_track_m
    rear = 0.0 if data.n_rear == 1 else vehicle.track_m
    if rear is None:
        missing.append("track_m")
    if front is None:
        missing.append("front_track_m")
    return None if front is None or rear is None else (front, rear)


def assess_dynamics(data: DynamicsInput) -> Dynamics:
    """Every case's estimates from what is known; the names of the missing inputs beside them."""
    vehicle = data.vehicle
    check_vehicle(vehicle)
    missing: list[str] = []
    empty = data.cases[0]
    h0 = _empty_cg_height(data, empty, missing)
    # The tipping axis runs through the outer wheels: an axle of two wheels needs its track, a
    # single wheel has none (reference section 9).
    tracks = _tracks(data, missing)
    stiffness = (vehicle.front_cornering_stiffness_n_per_rad, vehicle.rear_cornering_stiffness_n_per_rad)
    for name, value in zip(
        ("front_cornering_stiffness_n_per_rad", "rear_cornering_stiffness_n_per_rad"), stiffness, strict=True
    ):
        if value is None:
            missing.append(name)
    if data.has_load_items and h0 is not None:
        missing.append("load_items heights")
    results = []
    for case in data.cases:
        height = None if h0 is None or data.has_load_items else _case_height(data, case, h0, missing)
        threshold = (
            None
            if height is None or tracks is None
            else rollover_threshold_about_axis(
                front_track_m=tracks[0], rear_track_m=tracks[1], cg_height_m=height, lsf=case.lsf
            )
        )
        margin = speed = None
        front, rear = stiffness
        if front is not None and rear is not None:
            margin = understeer_margin(
                wheelbase_m=data.wheelbase_m,
                lsf=case.lsf,
                front_n_per_rad=front,
                rear_n_per_rad=rear,
                n_front=data.n_front,
                n_rear=data.n_rear,
            )
            speed = critical_speed_ms(
                wheelbase_m=data.wheelbase_m,
                mass_kg=case.total_kg,
                margin=margin,
                front_n_per_rad=front,
                rear_n_per_rad=rear,
                n_front=data.n_front,
                n_rear=data.n_rear,
            )
        results.append(
            CaseDynamics(
                occupants=case.occupants,
                cg_height_m=height,
                rollover_threshold_g=threshold,
                tilt_angle_deg=None if threshold is None else tilt_angle_deg(threshold),
                understeer_margin_nm_per_rad=margin,
                critical_speed_ms=speed,
            )
        )
    return Dynamics(empty_cg_height_m=h0, cases=tuple(results), missing=tuple(dict.fromkeys(missing)))


def _empty_cg_height(data: DynamicsInput, empty: CaseLoad, missing: list[str]) -> float | None:
    radius = data.vehicle.wheel_radius_m
    if data.cg_lift is not None and data.cg_height_m is not None:
        raise StabilityError(
            "cg_height_m", "one_of", "cg_height_m: give either cg_lift or cg_height_m, not both"
        )
    if data.cg_height_m is not None:
        return check_given_cg_height(data.cg_height_m, radius)
    if data.cg_lift is None:
        missing.append("cg_lift or cg_height_m")
        return None
    check_axle_lift(data.cg_lift, wheelbase_m=data.wheelbase_m, front_level_kg=data.front_level_kg)
    if radius is None:
        missing.append("wheel_radius_m")
        return None
    return cg_height_by_axle_lift(
        wheelbase_m=data.wheelbase_m,
        total_kg=data.weighed_total_kg or empty.total_kg,
        front_level_kg=data.front_level_kg,
        lift=data.cg_lift,
        wheel_radius_m=radius,
    )


def _case_height(data: DynamicsInput, case: CaseLoad, h0: float, missing: list[str]) -> float | None:
    """h_k; each occupant weighs the standard mass, or for a weighed case an equal share of the excess."""
    empty = data.cases[0]
    if case.occupants == 0:
        return h0
    heights = data.vehicle.seat_heights_m[: case.occupants]
    unknown = [f"seats[{i}].z_m" for i in range(case.occupants) if i >= len(heights) or heights[i] is None]
    if unknown:
        missing.extend(unknown)
        return None
    occupant_kg = (case.total_kg - empty.total_kg) / case.occupants
    known = [z for z in heights if z is not None]
    return case_cg_height(
        empty_total_kg=empty.total_kg, empty_cg_height_m=h0, occupant_kg=occupant_kg, seat_heights_m=known
    )


def rear_load_moved_kg(
    *,
    wheelbase_m: float,
    speed_ms: float,
    acceleration_ms2: float,
    mass_kg: float,
    cg_height_m: float | None,
    drag_area_m2: float,
    centre_of_pressure_height_m: float,
    air_density_kg_m3: float,
) -> float:
    """dR = (D h_cp + m a_x h) / WB, D = rho Cd A U^2 / 2, in kilograms on the scale."""
    drag_n = 0.5 * air_density_kg_m3 * drag_area_m2 * speed_ms**2
    inertia = 0.0 if acceleration_ms2 == 0 else mass_kg * acceleration_ms2 * _known(cg_height_m)
    return (drag_n * centre_of_pressure_height_m + inertia) / wheelbase_m / G


def margin_speed_ms(
    *,
    wheelbase_m: float,
    case: CaseLoad,
    drag_area_m2: float,
    centre_of_pressure_height_m: float,
    air_density_kg_m3: float,
    limit: float = LSF_LIMIT,
) -> float | None:
    """U = sqrt(2 (limit W - R) g WB / (rho Cd A h_cp)), limit 2/3 on a delta: drag alone uses up the
    margin; None if none."""
    margin_kg = limit * case.total_kg - case.rear_kg
    if margin_kg <= 0 or case.compliant is False:
        return None
    return math.sqrt(
        2 * margin_kg * G * wheelbase_m / (air_density_kg_m3 * drag_area_m2 * centre_of_pressure_height_m)
    )


def at_speed(
    data: DynamicsInput,
    dynamics: Dynamics,
    *,
    speed_kmh: float,
    acceleration_ms2: float = 0.0,
    air_density_kg_m3: float = DEFAULT_AIR_DENSITY,
) -> tuple[tuple[CaseAtSpeed, ...], tuple[str, ...]]:
    """Each case's LSF at a speed and acceleration, and the inputs missing for it."""
    check_speed(speed_kmh, acceleration_ms2)
    check_value(air_density_kg_m3, "air_density_kg_m3")
    area = data.vehicle.drag_area_m2
    height = data.vehicle.centre_of_pressure_height_m
    missing = [
        name for name, v in (("drag_area_m2", area), ("centre_of_pressure_height_m", height)) if v is None
    ]
    results = []
    for case, figures in zip(data.cases, dynamics.cases, strict=True):
        needs_cg = acceleration_ms2 != 0 and figures.cg_height_m is None
        if area is None or height is None or needs_cg:
            if needs_cg and "cg_height_m" not in missing:
                missing.append("cg_height_m")
            results.append(CaseAtSpeed(case.occupants, None, None, None))
            continue
        moved = rear_load_moved_kg(
            wheelbase_m=data.wheelbase_m,
            speed_ms=speed_kmh / KMH_PER_MS,
            acceleration_ms2=acceleration_ms2,
            mass_kg=case.total_kg,
            cg_height_m=figures.cg_height_m,
            drag_area_m2=area,
            centre_of_pressure_height_m=height,
            air_density_kg_m3=air_density_kg_m3,
        )
        lsf = (case.rear_kg + moved) / case.total_kg
        # Nothing moved (standing still): the exact static verdict, not a float comparison at 2/3.
        compliant = case.compliant if moved == 0 and case.compliant is not None else lsf < data.limit
        margin = margin_speed_ms(
            wheelbase_m=data.wheelbase_m,
            case=case,
            drag_area_m2=area,
            centre_of_pressure_height_m=height,
            air_density_kg_m3=air_density_kg_m3,
            limit=data.limit,
        )
        results.append(
            CaseAtSpeed(
                occupants=case.occupants,
                lsf_at_speed=lsf,
                compliant_at_speed=compliant,
                margin_speed_kmh=None if margin is None else margin * KMH_PER_MS,
            )
        )
    return tuple(results), tuple(missing)


def _known(value: float | None) -> float:
    if value is None:  # pragma: no cover - at_speed checks first
        raise ValueError("cg height needed")
    return value


def _g(value: float) -> str:
    """A figure for messages: up to 4 significant decimals, no trailing zeros."""
    return f"{value:.4f}".rstrip("0").rstrip(".")
