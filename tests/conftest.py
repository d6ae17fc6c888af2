"""Shared fixtures: one fresh database per run (SQLite file or a new PostgreSQL database),
migrated once by Alembic, emptied after every test; an API client with a station key."""

from __future__ import annotations

import os
import uuid
from collections.abc import Iterator
from pathlib import Path

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import Engine, create_engine, text
from sqlalchemy.engine import make_url
from sqlalchemy.orm import Session

from app import config, db
from app.certificates.guard import immutability_lifted
from app.db import Base
from app.main import create_app
from app.migrate import upgrade
from app.stations.service import create_station

TEST_DATABASE_ENV = "TRIKECERT_TEST_DATABASE_URL"


def _fresh_postgres(server_url: str) -> tuple[str, str]:
    """Create a new, empty database on the server; return its URL and name."""
    name = f"trikecert_test_{uuid.uuid4().hex[:12]}"
    admin = create_engine(server_url, isolation_level="AUTOCOMMIT")
    with admin.connect() as connection:
        connection.execute(text(f'CREATE DATABASE "{name}"'))
    admin.dispose()
    return make_url(server_url).set(database=name).render_as_string(hide_password=False), name


def _drop_postgres(server_url: str, name: str) -> None:
    admin = create_engine(server_url, isolation_level="AUTOCOMMIT")
    with admin.connect() as connection:
        connection.execute(text(f'DROP DATABASE IF EXISTS "{name}" WITH (FORCE)'))
    admin.dispose()


@pytest.fixture(scope="session")
def database_url(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    """The URL of this run's fresh database, migrated to head."""
    server_url = os.environ.get(TEST_DATABASE_ENV, "")
    created: str | None = None
    if server_url.startswith("postgresql"):
        url, created = _fresh_postgres(server_url)
    else:
        url = f"sqlite:///{Path(tmp_path_factory.mktemp('db')) / 'trikecert-test.db'}"
    previous = os.environ.get("TRIKECERT_DATABASE_URL")
    os.environ["TRIKECERT_DATABASE_URL"] = url
    os.environ["TRIKECERT_ENVIRONMENT"] = "test"
    _clear_caches()
    upgrade(db.get_engine())
    yield url
    db.get_engine().dispose()
    _clear_caches()
    if previous is None:
        os.environ.pop("TRIKECERT_DATABASE_URL", None)
    else:
        os.environ["TRIKECERT_DATABASE_URL"] = previous
    if created:
        _drop_postgres(server_url, created)


def _clear_caches() -> None:
    config.get_settings.cache_clear()
    db.get_engine.cache_clear()
    db.get_sessionmaker.cache_clear()


@pytest.fixture
def engine(database_url: str) -> Iterator[Engine]:
    """The run's engine; every table is emptied after the test."""
    engine = db.get_engine()
    yield engine
    with engine.begin() as connection, immutability_lifted(connection):
        for table in reversed(Base.metadata.sorted_tables):
            connection.execute(table.delete())


@pytest.fixture
def session(engine: Engine) -> Iterator[Session]:
    """A session on the run's database."""
    with db.get_sessionmaker()() as session:
        yield session


@pytest.fixture
def client(engine: Engine) -> Iterator[TestClient]:
    """A TestClient on a fresh app (no station key)."""
    with TestClient(create_app(), raise_server_exceptions=False) as client:
        yield client


@pytest.fixture
def station_key(session: Session) -> str:
    """The API key of a new station."""
    _station, key = create_station(session, name="Test weighbridge")
    return key


@pytest.fixture
def api(client: TestClient, station_key: str) -> TestClient:
    """The TestClient signed as a station."""
    client.headers["Authorization"] = f"Bearer {station_key}"
    return client
