"""Beyond the static test: the reference's sections 4 and 5 to their printed digits, own vehicles, refusals.

Each figure is checked twice: against the reference's printed value, and against an independent
computation written here from first principles (moments of forces about the tipping line and the
rear contact, the bicycle model's state matrix whose determinant, eq. 21's constant term, vanishes
at the critical speed, a forward model of the tilted weighing), never by calling the formula again.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import pytest

from app.stability import StabilityError
from app.stability.dynamics import (
    AxleLift,
    CaseLoad,
    DynamicsInput,
    G,
    VehicleDynamics,
    assess_dynamics,
    at_speed,
)

OCCUPANT = 72.0


def study_cases(
    w: float = 359.0, r: float = 250.0, wb: float = 2.0, seats: tuple[float, ...] = ()
) -> tuple[CaseLoad, ...]:
    """Cumulative cases by moments about the front contact (the static core's rule, in floats)."""
    seats = seats or (0.9303, 1.6303, 1.6303, 1.6303)
    cases = [CaseLoad(0, w, r)]
    for k, x in enumerate(seats, start=1):
        w, r = w + OCCUPANT, r + OCCUPANT * x / wb
        cases.append(CaseLoad(k, w, r))
    return tuple(cases)


STUDY_VEHICLE = VehicleDynamics(
    track_m=1.15,
    wheel_radius_m=0.19,
    seat_heights_m=(0.75, 0.80, 0.80, 0.80),
    front_cornering_stiffness_n_per_rad=8000.0,
    rear_cornering_stiffness_n_per_rad=8000.0,
    drag_area_m2=1.6,
    centre_of_pressure_height_m=0.9,
)
STUDY = DynamicsInput(
    wheelbase_m=2.0,
    front_level_kg=108.0,
    cases=study_cases(),
    vehicle=STUDY_VEHICLE,
    cg_lift=AxleLift(lift_height_m=0.40, front_kg=94.8),
)


# ---- the independent computations ------------------------------------------------------------


def lifted_front_reading(*, w: float, f0: float, wb: float, r: float, h: float, lift: float) -> float:
    """Forward model of the tilted weighing: rotate the CG about the rear axle, take moments there."""
    phi = math.asin(lift / wb)
    l2 = wb * f0 / w  # CG ahead of the rear axle, along the axle line
    ahead = l2 * math.cos(phi) - (h - r) * math.sin(phi)  # horizontal, once tilted
    return w * ahead / (wb * math.cos(phi))


def cross(a: tuple[float, float, float], b: tuple[float, float, float]) -> tuple[float, float, float]:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a: tuple[float, ...], b: tuple[float, ...]) -> float:
    return sum(x * y for x, y in zip(a, b, strict=True))


def tipping_moment(*, l1: float, h: float, wb: float, track: float, lateral_g: float) -> float:
    """Moment about the line front contact - outer rear contact of gravity and a lateral force (per kg*g)."""
    axis = (wb, track / 2, 0.0)
    cg = (l1, 0.0, h)
    moment = tuple(
        g + f for g, f in zip(cross(cg, (0.0, 0.0, -1.0)), cross(cg, (0.0, lateral_g, 0.0)), strict=True)
    )
    return dot(moment, axis)


def bisect(f: Callable[[float], float], low: float, high: float) -> float:
    """The root of f between low and high, where f changes sign."""
    f_low = f(low)
    for _ in range(200):
        mid = (low + high) / 2
        if (f(mid) > 0) == (f_low > 0):
            low, f_low = mid, f(mid)
        else:
            high = mid
    return (low + high) / 2


def independent_threshold(*, l1: float, h: float, wb: float, track: float) -> float:
    """The lateral acceleration (g) at which the tipping moment changes sign."""
    return bisect(lambda a: tipping_moment(l1=l1, h=h, wb=wb, track=track, lateral_g=a), 0.0, 10.0)


def independent_tilt_deg(*, l1: float, h: float, wb: float, track: float) -> float:
    """The tilt-table angle: gravity's components sin and cos of the angle, moment about the line."""

    def moment(theta: float) -> float:
        axis = (wb, track / 2, 0.0)
        cg = (l1, 0.0, h)
        return dot(cross(cg, (0.0, math.sin(theta), -math.cos(theta))), axis)

    return math.degrees(bisect(moment, 0.0, math.pi / 2 - 1e-9))


def yaw_determinant(*, speed: float, m: float, l1: float, l2: float, caf: float, car: float) -> float:
    """Determinant of the bicycle model's (sideslip, yaw) state matrix, eq. 21's constant term / (m Iz)."""
    iz = 150.0  # any positive yaw inertia: the sign change does not depend on it
    cf, cr = caf, 2 * car  # one front tyre, two rear tyres
    a11 = -(cf + cr) / (m * speed)
    a12 = -(l1 * cf - l2 * cr) / (m * speed) - speed
    a21 = -(l1 * cf - l2 * cr) / (iz * speed)
    a22 = -(l1**2 * cf + l2**2 * cr) / (iz * speed)
    return a11 * a22 - a12 * a21


def independent_critical_kmh(*, m: float, l1: float, l2: float, caf: float, car: float) -> float | None:
    """The speed where the determinant turns negative (a real positive eigenvalue), or None."""

    def det(u: float) -> float:
        return yaw_determinant(speed=u, m=m, l1=l1, l2=l2, caf=caf, car=car)

    if det(1000.0) > 0:
        return None
    return bisect(det, 0.1, 1000.0) * 3.6


def independent_lsf_at_speed(
    *, case: CaseLoad, wb: float, kmh: float, accel: float, h: float, cda: float, hcp: float, rho: float
) -> float:
    """Moments about the rear contact: front reaction N_f = (W g L2 - D hcp - m a h) / WB."""
    u = kmh / 3.6
    drag = rho * cda * u * u / 2
    l2 = wb * (case.total_kg - case.rear_kg) / case.total_kg
    front_n = (case.total_kg * G * l2 - drag * hcp - case.total_kg * accel * h) / wb
    return 1 - front_n / (case.total_kg * G)


# ---- the reference's worked examples ---------------------------------------------------------

STUDY_RESULT = assess_dynamics(STUDY)

# case, h_k (4 d.p.), threshold g (4), tilt deg (2), critical speed km/h (1) or None
PRINTED = [
    (0, 0.5503, 0.7277, 36.04, 113.8),
    (1, 0.5836, 0.6480, 32.94, None),
    (2, 0.6146, 0.6365, 32.47, 142.1),
    (3, 0.6378, 0.6285, 32.15, 88.8),
    (4, 0.6559, 0.6227, 31.91, 70.0),
]


def test_the_axle_lift_gives_the_printed_cg_height_and_the_forward_model_agrees() -> None:
    h0 = STUDY_RESULT.empty_cg_height_m
    assert h0 is not None
    assert round(h0, 4) == 0.5503
    assert lifted_front_reading(w=359, f0=108, wb=2, r=0.19, h=h0, lift=0.4) == pytest.approx(94.8, abs=1e-9)
    assert STUDY_RESULT.missing == ()


@pytest.mark.parametrize(("occupants", "height", "threshold", "tilt", "critical"), PRINTED)
def test_each_case_reproduces_the_printed_figures(
    occupants: int, height: float, threshold: float, tilt: float, critical: float | None
) -> None:
    case = STUDY.cases[occupants]
    figures = STUDY_RESULT.cases[occupants]
    assert figures.cg_height_m is not None
    assert figures.rollover_threshold_g is not None
    assert figures.tilt_angle_deg is not None
    assert round(figures.cg_height_m, 4) == height
    assert round(figures.rollover_threshold_g, 4) == threshold
    assert round(figures.tilt_angle_deg, 2) == tilt
    assert (None if figures.critical_speed_kmh is None else round(figures.critical_speed_kmh, 1)) == critical

    # independently: the CG as the weighted mean of point masses, then moments about the tipping line
    masses = [(359.0, STUDY_RESULT.empty_cg_height_m)] + [
        (OCCUPANT, z) for z in (0.75, 0.8, 0.8, 0.8)[:occupants]
    ]
    h = sum(m * z for m, z in masses if z is not None) / sum(m for m, _ in masses)
    l1 = 2.0 * case.rear_kg / case.total_kg
    assert figures.cg_height_m == pytest.approx(h, rel=1e-12)
    assert figures.rollover_threshold_g == pytest.approx(
        independent_threshold(l1=l1, h=h, wb=2, track=1.15), rel=1e-9
    )
    assert figures.tilt_angle_deg == pytest.approx(
        independent_tilt_deg(l1=l1, h=h, wb=2, track=1.15), rel=1e-9
    )
    expected = independent_critical_kmh(m=case.total_kg, l1=l1, l2=2 - l1, caf=8000, car=8000)
    if expected is None:
        assert figures.critical_speed_kmh is None
    else:
        assert figures.critical_speed_kmh == pytest.approx(expected, rel=1e-9)


def test_the_driver_alone_understeers_with_the_printed_margin() -> None:
    driver = STUDY_RESULT.cases[1]
    assert driver.understeer_margin_nm_per_rad is not None
    assert round(driver.understeer_margin_nm_per_rad, 1) == 427.9
    # identical tyres: S = C WB (2 - 3 LSF), the static rule in another form
    assert driver.understeer_margin_nm_per_rad == pytest.approx(
        8000 * 2 * (2 - 3 * STUDY.cases[1].lsf), rel=1e-12
    )
    assert [
        c.understeer_margin_nm_per_rad is not None and c.understeer_margin_nm_per_rad > 0
        for c in STUDY_RESULT.cases
    ] == [
        False,
        True,
        False,
        False,
        False,
    ]


def test_drag_at_60_kmh_moves_12_2_kg_rearward_and_the_driver_case_turns_non_compliant() -> None:
    cases, missing = at_speed(STUDY, STUDY_RESULT, speed_kmh=60)
    driver = cases[1]
    assert missing == ()
    assert driver.lsf_at_speed is not None
    moved = (driver.lsf_at_speed - STUDY.cases[1].lsf) * STUDY.cases[1].total_kg
    assert round(moved, 1) == 12.2
    assert round(0.5 * 1.2 * 1.6 * (60 / 3.6) ** 2, 1) == 266.7
    assert round(driver.lsf_at_speed, 4) == 0.6861
    assert driver.compliant_at_speed is False
    assert driver.lsf_at_speed == pytest.approx(
        independent_lsf_at_speed(case=STUDY.cases[1], wb=2, kmh=60, accel=0, h=0, cda=1.6, hcp=0.9, rho=1.2),
        rel=1e-12,
    )


def test_the_drivers_static_margin_is_used_up_by_drag_at_33_6_kmh_with_either_g() -> None:
    cases, _ = at_speed(STUDY, STUDY_RESULT, speed_kmh=0)
    speed = cases[1].margin_speed_kmh
    assert speed is not None
    assert round(speed, 1) == 33.6
    # the reference turns kg into N with 9.81: the printed digit is the same
    margin_kg = 2 / 3 * STUDY.cases[1].total_kg - STUDY.cases[1].rear_kg
    assert round(math.sqrt(2 * margin_kg * 9.81 * 2 / (1.2 * 1.6 * 0.9)) * 3.6, 1) == 33.6
    independent = bisect(
        lambda kmh: (
            independent_lsf_at_speed(
                case=STUDY.cases[1], wb=2, kmh=kmh, accel=0, h=0, cda=1.6, hcp=0.9, rho=1.2
            )
            - 2 / 3
        ),
        0.0,
        200.0,
    )
    assert speed == pytest.approx(independent, rel=1e-9)
    # standing still the driver case complies; every other case is NC already and has no margin speed
    assert [c.compliant_at_speed for c in cases] == [False, True, False, False, False]
    assert [c.margin_speed_kmh is None for c in cases] == [True, False, True, True, True]


# ---- vehicles of our own ---------------------------------------------------------------------

OWN = [
    # label, W, R, WB, seats x, seat z, track, radius, F0, Fphi, H, CaF, CaR, Cd*A, h_cp, km/h, a_x
    (
        "long rear bench",
        410.0,
        240.0,
        2.2,
        (0.95, 1.75, 1.75),
        (0.78, 0.85, 0.85),
        1.25,
        0.2,
        170.0,
        155.0,
        0.35,
        9000,
        7500,
        1.8,
        0.95,
        45,
        1.5,
    ),
    (
        "cargo box",
        300.0,
        190.0,
        1.9,
        (0.85,),
        (0.7,),
        1.05,
        0.18,
        110.0,
        101.5,
        0.3,
        7000,
        9500,
        1.4,
        0.85,
        70,
        -2.0,
    ),
    (
        "tall cab",
        520.0,
        330.0,
        2.4,
        (1.0, 1.9, 1.9, 1.9, 1.9),
        (0.9, 1.0, 1.0, 1.0, 1.0),
        1.3,
        0.22,
        190.0,
        172.0,
        0.5,
        12000,
        10000,
        2.2,
        1.1,
        30,
        2.5,
    ),
]


@pytest.mark.parametrize("row", OWN, ids=[r[0] for r in OWN])
def test_own_vehicles_agree_with_the_independent_computation(row: tuple[Any, ...]) -> None:
    _, w, r, wb, xs, zs, track, radius, f0, fphi, lift, caf, car, cda, hcp, kmh, accel = row
    vehicle = VehicleDynamics(track, radius, zs, caf, car, cda, hcp)
    data = DynamicsInput(wb, f0, study_cases(w, r, wb, xs), vehicle, AxleLift(lift, fphi))
    result = assess_dynamics(data)
    h0 = result.empty_cg_height_m
    assert h0 is not None
    assert lifted_front_reading(w=w, f0=f0, wb=wb, r=radius, h=h0, lift=lift) == pytest.approx(
        fphi, rel=1e-12
    )
    speeds, missing = at_speed(data, result, speed_kmh=kmh, acceleration_ms2=accel)
    assert missing == ()
    for case, figures, moving in zip(data.cases, result.cases, speeds, strict=True):
        masses = [(w, h0)] + [(OCCUPANT, z) for z in zs[: case.occupants]]
        h = sum(m * z for m, z in masses) / sum(m for m, _ in masses)
        l1 = wb * case.rear_kg / case.total_kg
        assert figures.cg_height_m == pytest.approx(h, rel=1e-12)
        assert figures.rollover_threshold_g == pytest.approx(
            independent_threshold(l1=l1, h=h, wb=wb, track=track), rel=1e-9
        )
        assert figures.tilt_angle_deg == pytest.approx(
            independent_tilt_deg(l1=l1, h=h, wb=wb, track=track), rel=1e-9
        )
        expected = independent_critical_kmh(m=case.total_kg, l1=l1, l2=wb - l1, caf=caf, car=car)
        if expected is None:
            assert figures.critical_speed_kmh is None
        else:
            assert figures.critical_speed_kmh == pytest.approx(expected, rel=1e-9)
        lsf = independent_lsf_at_speed(case=case, wb=wb, kmh=kmh, accel=accel, h=h, cda=cda, hcp=hcp, rho=1.2)
        assert moving.lsf_at_speed == pytest.approx(lsf, rel=1e-12)
        assert moving.compliant_at_speed is (lsf < 2 / 3)


def test_what_is_unknown_is_null_and_named() -> None:
    bare = assess_dynamics(replace(STUDY, vehicle=VehicleDynamics(), cg_lift=None))
    assert bare.missing == (
        "cg_lift or cg_height_m",
        "track_m",
        "front_cornering_stiffness_n_per_rad",
        "rear_cornering_stiffness_n_per_rad",
    )
    assert all(
        (c.cg_height_m, c.rollover_threshold_g, c.understeer_margin_nm_per_rad, c.critical_speed_ms)
        == (None,) * 4
        for c in bare.cases
    )
    no_z = assess_dynamics(replace(STUDY, vehicle=replace(STUDY_VEHICLE, seat_heights_m=(0.75,))))
    assert no_z.missing == ("seats[1].z_m", "seats[2].z_m", "seats[3].z_m")
    assert [c.rollover_threshold_g is None for c in no_z.cases] == [False, False, True, True, True]
    given = assess_dynamics(replace(STUDY, cg_lift=None, cg_height_m=0.6))
    assert given.empty_cg_height_m == 0.6
    speeds, missing = at_speed(
        replace(STUDY, vehicle=replace(STUDY_VEHICLE, drag_area_m2=None)), STUDY_RESULT, speed_kmh=50
    )
    assert missing == ("drag_area_m2",)
    assert all(s.lsf_at_speed is None for s in speeds)


# ---- refusals ---------------------------------------------------------------------------------

REFUSALS: list[tuple[str, dict[str, Any], str, str, str]] = [
    (
        "raised wheel heavier than level",
        {"cg_lift": AxleLift(0.4, 108.0)},
        "cg_lift.front_kg",
        "less_than_level",
        "108",
    ),
    (
        "raised wheel weighs nothing",
        {"cg_lift": AxleLift(0.4, 0.0)},
        "cg_lift.front_kg",
        "positive",
        "more than 0",
    ),
    (
        "lift as high as the wheelbase",
        {"cg_lift": AxleLift(2.0, 94.8)},
        "cg_lift.lift_height_m",
        "below_wheelbase",
        "2 m",
    ),
    ("no lift", {"cg_lift": AxleLift(0.0, 94.8)}, "cg_lift.lift_height_m", "positive", "more than 0"),
    (
        "CG at the wheel centre",
        {"cg_lift": None, "cg_height_m": 0.19},
        "cg_height_m",
        "above_wheel_centre",
        "0.19",
    ),
    ("CG height not a number", {"cg_lift": None, "cg_height_m": math.nan}, "cg_height_m", "finite", "finite"),
    ("both lift and height", {"cg_height_m": 0.6}, "cg_height_m", "one_of", "not both"),
    ("zero track", {"vehicle": replace(STUDY_VEHICLE, track_m=0.0)}, "track_m", "positive", "rear track"),
    ("negative track", {"vehicle": replace(STUDY_VEHICLE, track_m=-1.15)}, "track_m", "positive", "-1.15"),
    ("absurd track", {"vehicle": replace(STUDY_VEHICLE, track_m=11.5)}, "track_m", "range", "at most 3"),
    (
        "zero radius",
        {"vehicle": replace(STUDY_VEHICLE, wheel_radius_m=0.0)},
        "wheel_radius_m",
        "positive",
        "radius",
    ),
    (
        "zero front stiffness",
        {"vehicle": replace(STUDY_VEHICLE, front_cornering_stiffness_n_per_rad=0.0)},
        "front_cornering_stiffness_n_per_rad",
        "positive",
        "front tyre",
    ),
    (
        "negative rear stiffness",
        {"vehicle": replace(STUDY_VEHICLE, rear_cornering_stiffness_n_per_rad=-8000.0)},
        "rear_cornering_stiffness_n_per_rad",
        "positive",
        "rear tyre",
    ),
    (
        "infinite stiffness",
        {"vehicle": replace(STUDY_VEHICLE, rear_cornering_stiffness_n_per_rad=math.inf)},
        "rear_cornering_stiffness_n_per_rad",
        "finite",
        "finite",
    ),
    (
        "zero drag area",
        {"vehicle": replace(STUDY_VEHICLE, drag_area_m2=0.0)},
        "drag_area_m2",
        "positive",
        "drag area",
    ),
    (
        "negative centre of pressure",
        {"vehicle": replace(STUDY_VEHICLE, centre_of_pressure_height_m=-0.9)},
        "centre_of_pressure_height_m",
        "positive",
        "centre of pressure",
    ),
    (
        "seat too low",
        {"vehicle": replace(STUDY_VEHICLE, seat_heights_m=(0.75, 0.1))},
        "seats[1].z_m",
        "range",
        "between 0.2 and 2.0",
    ),
    (
        "seat too high",
        {"vehicle": replace(STUDY_VEHICLE, seat_heights_m=(2.5,))},
        "seats[0].z_m",
        "range",
        "2.5",
    ),
]


@pytest.mark.parametrize(
    ("label", "changes", "field", "rule", "words"), REFUSALS, ids=[r[0] for r in REFUSALS]
)
def test_every_refusal_names_the_field_and_the_rule(
    label: str, changes: dict[str, Any], field: str, rule: str, words: str
) -> None:
    with pytest.raises(StabilityError) as refused:
        assess_dynamics(replace(STUDY, **changes))
    assert (refused.value.field, refused.value.rule) == (field, rule)
    assert refused.value.message.startswith(f"{field}: ")
    assert words in refused.value.message


SPEED_REFUSALS = [
    ({"speed_kmh": -1.0}, "speed_kmh", "range"),
    ({"speed_kmh": 250.0}, "speed_kmh", "range"),
    ({"speed_kmh": math.inf}, "speed_kmh", "finite"),
    ({"speed_kmh": 50.0, "acceleration_ms2": 12.0}, "acceleration_ms2", "range"),
    ({"speed_kmh": 50.0, "acceleration_ms2": math.nan}, "acceleration_ms2", "finite"),
    ({"speed_kmh": 50.0, "air_density_kg_m3": 0.0}, "air_density_kg_m3", "positive"),
]


@pytest.mark.parametrize(("arguments", "field", "rule"), SPEED_REFUSALS)
def test_a_bad_speed_acceleration_or_air_density_is_refused(
    arguments: dict[str, float], field: str, rule: str
) -> None:
    with pytest.raises(StabilityError) as refused:
        at_speed(STUDY, STUDY_RESULT, **arguments)
    assert (refused.value.field, refused.value.rule) == (field, rule)
    assert refused.value.message.startswith(f"{field}: ")


def test_accelerating_without_a_known_cg_height_is_named_not_guessed() -> None:
    data = replace(STUDY, cg_lift=None)
    speeds, missing = at_speed(data, assess_dynamics(data), speed_kmh=40, acceleration_ms2=1.0)
    assert missing == ("cg_height_m",)
    assert all(s.lsf_at_speed is None for s in speeds)
    # drag alone needs no CG height
    speeds, missing = at_speed(data, assess_dynamics(data), speed_kmh=40)
    assert missing == ()
    assert all(s.lsf_at_speed is not None for s in speeds)


def test_exactly_two_thirds_stays_non_compliant_standing_still_whatever_the_floats_say() -> None:
    # a = 103.2, b = 91.3, c = 115.1: LSF exactly 2/3 (NC), which floats put a hair below 2/3
    case = CaseLoad(0, 309.6, 206.4, compliant=False)
    data = replace(STUDY, front_level_kg=103.2, cases=(case,), cg_lift=None)
    speeds, _ = at_speed(data, assess_dynamics(data), speed_kmh=0)
    assert speeds[0].compliant_at_speed is False
    assert speeds[0].margin_speed_kmh is None
