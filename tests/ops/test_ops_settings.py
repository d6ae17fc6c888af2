"""Production refuses placeholder secrets; development and tests do not care."""

from __future__ import annotations

import pytest
from pydantic import ValidationError

from app.config import Settings

PUBLIC = "https://trikecert.example.gov"


@pytest.mark.parametrize(
    "url",
    [
        "postgresql+psycopg://trikecert:changeme@db:5432/trikecert",
        "postgresql+psycopg://trikecert:password@db:5432/trikecert",
        "postgresql+psycopg://trikecert:short@db:5432/trikecert",
        "postgresql+psycopg://trikecert:@db:5432/trikecert",
    ],
    ids=["changeme", "password", "too-short", "empty"],
)
def test_production_refuses_a_placeholder_database_password(url: str) -> None:
    with pytest.raises(ValidationError, match="TRIKECERT_DATABASE_URL"):
        Settings(environment="production", database_url=url, base_url=PUBLIC)


def test_production_accepts_a_real_secret_and_development_accepts_anything() -> None:
    real = "postgresql+psycopg://trikecert:Xq8-v2Lr0pZ7w1Tn@db:5432/trikecert"
    assert Settings(environment="production", database_url=real, base_url=PUBLIC).database_url == real
    weak = "postgresql+psycopg://trikecert:changeme@db:5432/trikecert"
    assert Settings(environment="development", database_url=weak).database_url == weak
