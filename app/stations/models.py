"""Station tables: a weighbridge site, its scale and the hash of its API key; its rate-limit window."""

from __future__ import annotations

from datetime import date, datetime
from decimal import Decimal

from sqlalchemy import BigInteger, Boolean, Date, ForeignKey, Integer, Numeric, String
from sqlalchemy.orm import Mapped, mapped_column

from app.db import Base, UTCDateTime, utcnow


class Station(Base):
    """A weighbridge station that submits readings over the API, with its scale's calibration."""

    __tablename__ = "station"

    id: Mapped[int] = mapped_column(primary_key=True)
    name: Mapped[str] = mapped_column(String(120), unique=True)
    key_hash: Mapped[str] = mapped_column(String(64), unique=True)
    key_prefix: Mapped[str] = mapped_column(String(16))
    active: Mapped[bool] = mapped_column(Boolean, default=True)
    created_at: Mapped[datetime] = mapped_column(UTCDateTime(), default=utcnow)
    key_rotated_at: Mapped[datetime | None] = mapped_column(UTCDateTime())

    location: Mapped[str | None] = mapped_column(String(200))
    operator_contact: Mapped[str | None] = mapped_column(String(200))
    # The scale: its calibration certificate, the last day it is valid (UTC), capacity and division (e).
    calibration_certificate: Mapped[str | None] = mapped_column(String(64))
    calibration_valid_until: Mapped[date | None] = mapped_column(Date)
    capacity_kg: Mapped[Decimal | None] = mapped_column(Numeric(10, 3))
    division_kg: Mapped[Decimal | None] = mapped_column(Numeric(8, 3))


class StationRateWindow(Base):
    """A station key's fixed-window request counter, shared by every worker through the database."""

    __tablename__ = "station_rate_window"

    station_id: Mapped[int] = mapped_column(ForeignKey("station.id", ondelete="CASCADE"), primary_key=True)
    window_start: Mapped[int] = mapped_column(BigInteger)  # Unix seconds at which the window opened
    request_count: Mapped[int] = mapped_column(Integer)
