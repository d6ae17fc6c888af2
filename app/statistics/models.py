"""Stored counts of closed days: derived data, not records.

Each row is a count of inspections or certificates that can be made again at any time from the
records themselves (inspection, certificate, certificate_revocation), which are append-only: a local
day that has ended never gains or loses an inspection, so its counts, once taken, stay true. They
are kept only so the statistics page does not count a whole year again on every visit; deleting
them loses nothing (they are counted again on the next visit). Days are local days of a named zone
(the display zone when they were counted), and each day keeps the UTC bounds it was counted over:
a day whose bounds differ from the zone's rules today is counted again.
"""

from __future__ import annotations

from datetime import date, datetime

from sqlalchemy import Date, Index, Integer, String
from sqlalchemy.orm import Mapped, mapped_column

from app.db import Base, UTCDateTime

# The station_id of inspections entered by officers in the pages (they have none); no station has id 0.
NO_STATION = 0


class StatisticsDay(Base):
    """One closed local day of a zone that has been counted: its UTC bounds, its inspections at every
    station together, and its certificates."""

    __tablename__ = "statistics_day"

    zone: Mapped[str] = mapped_column(String(64), primary_key=True)
    day: Mapped[date] = mapped_column(Date, primary_key=True)
    starts_at: Mapped[datetime] = mapped_column(UTCDateTime())
    ends_at: Mapped[datetime] = mapped_column(UTCDateTime())
    inspections: Mapped[int] = mapped_column(Integer, default=0)
    compliant: Mapped[int] = mapped_column(Integer, default=0)
    certificates_issued: Mapped[int] = mapped_column(Integer, default=0)
    refusals_issued: Mapped[int] = mapped_column(Integer, default=0)
    certificates_revoked: Mapped[int] = mapped_column(Integer, default=0)


class StatisticsDayStation(Base):
    """A counted day's inspections at one station (NO_STATION: the officers' pages); none: no row."""

    __tablename__ = "statistics_day_station"
    # A period's sums per station read from the index alone (PostgreSQL: an index-only scan).
    __table_args__ = (
        Index(
            "ix_statistics_day_station_zone_day",
            "zone",
            "day",
            postgresql_include=["station_id", "inspections", "compliant"],
        ),
    )

    zone: Mapped[str] = mapped_column(String(64), primary_key=True)
    day: Mapped[date] = mapped_column(Date, primary_key=True)
    station_id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=False)
    inspections: Mapped[int] = mapped_column(Integer)
    compliant: Mapped[int] = mapped_column(Integer)


class StatisticsMonth(Base):
    """A calendar month of a zone whose per-station sums are stored: every day of it was stored first."""

    __tablename__ = "statistics_month"

    zone: Mapped[str] = mapped_column(String(64), primary_key=True)
    month: Mapped[date] = mapped_column(Date, primary_key=True)  # its first day


class StatisticsMonthStation(Base):
    """A stored month's inspections at one station, the sum of its days' (none: no row)."""

    __tablename__ = "statistics_month_station"

    zone: Mapped[str] = mapped_column(String(64), primary_key=True)
    month: Mapped[date] = mapped_column(Date, primary_key=True)
    station_id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=False)
    inspections: Mapped[int] = mapped_column(Integer)
    compliant: Mapped[int] = mapped_column(Integer)


class StatisticsHour(Base):
    """A closed whole UTC hour of the open days whose inspections are counted (by station, in
    StatisticsHourStation), so today's counts add up its closed hours and count only the last ones
    live. Zone-free: an hour is the same in every zone. Pruned once its days have long closed."""

    __tablename__ = "statistics_hour"

    starts_at: Mapped[datetime] = mapped_column(UTCDateTime(), primary_key=True)
    ends_at: Mapped[datetime] = mapped_column(UTCDateTime())


class StatisticsHourStation(Base):
    """A counted hour's inspections at one station (NO_STATION: the officers' pages); none: no row."""

    __tablename__ = "statistics_hour_station"

    starts_at: Mapped[datetime] = mapped_column(UTCDateTime(), primary_key=True)
    station_id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=False)
    inspections: Mapped[int] = mapped_column(Integer)
    compliant: Mapped[int] = mapped_column(Integer)
