"""Settings from the environment (prefix TRIKECERT_), read once and cached."""

from __future__ import annotations

from decimal import Decimal
from functools import lru_cache
from typing import Literal

from pydantic import Field, model_validator
from pydantic_settings import BaseSettings, SettingsConfigDict

from sqlalchemy.engine import make_url

from app.stability import Rules

PLACEHOLDER_SECRETS = {"", "changeme", "change-me", "password", "postgres", "secret", "placeholder", "trikecert"}


class Settings(BaseSettings):
    """Every knob of the service; each one can be set as TRIKECERT_<NAME> in the environment."""

    model_config = SettingsConfigDict(env_prefix="TRIKECERT_", env_file=".env", extra="ignore")

    environment: Literal["development", "test", "production"] = "development"
    database_url: str = "sqlite:///./trikecert.db"
    occupant_mass_kg: Decimal = Field(default=Decimal("72"), ge=20, le=250)
    sum_tolerance: Decimal = Field(default=Decimal("0.01"), gt=0, le=Decimal("0.1"))
    max_body_bytes: int = 1024 * 1024
    page_size: int = Field(default=50, ge=1, le=500)
    session_idle_minutes: int = 30
    session_absolute_hours: int = 12
    login_max_failures: int = 5
    login_lockout_minutes: int = 15
    cookie_secure: bool = False
    # Pages show times and count "today" in this zone; everything is stored in UTC.
    display_timezone: str = "Africa/Lagos"

    @model_validator(mode="after")
    def refuse_placeholder_secrets(self) -> Settings:
        """Outside development and tests, a database password must be a real secret."""
        if self.environment == "production":
            password = make_url(self.database_url).password
            if password is not None and (len(password) < 12 or password.lower() in PLACEHOLDER_SECRETS):
                raise ValueError(
                    "TRIKECERT_DATABASE_URL: the database password is a placeholder or shorter than 12 "
                    "characters; set a real secret in production"
                )
        return self

    def rules(self) -> Rules:
        """The stability rules in force under these settings."""
        return Rules(occupant_mass_kg=self.occupant_mass_kg, sum_tolerance=self.sum_tolerance)


@lru_cache
def get_settings() -> Settings:
    """The process-wide settings (tests clear the cache to change them)."""
    return Settings()
