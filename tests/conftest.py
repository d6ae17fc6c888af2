"""Shared fixtures: one fresh database per run (SQLite file or a new PostgreSQL database),
migrated once by Alembic, emptied after every test; an API client with a station key.

On PostgreSQL the run migrates as the server URL's (owner) role and the app, with everything the
tests do through `engine` and `session`, connects as an app role of its own, created for the run
(app/grants.py): so every test shows the service works with only the rights the app role has.
Clean-up and `owner_engine` use the owner."""

from __future__ import annotations

import gc
import os
import re
import secrets
import uuid
from collections.abc import Callable, Iterator, Mapping
from datetime import datetime
from pathlib import Path

import pytest
from applications import application
from emptied import empty_every_table
from fastapi.testclient import TestClient
from password_cost import cheap_password_hashing
from regex_classes import keep_character_classes
from sqlalchemy import Engine, bindparam, create_engine, text, update
from sqlalchemy.engine import make_url
from sqlalchemy.exc import OperationalError
from sqlalchemy.orm import Session

from app import config, db
from app.certificates.answer_cache import forget_answers
from app.certificates.guard import immutability_lifted
from app.certificates.trust_bundle import forget_bundles
from app.db import make_engine
from app.grants import grant_app_role
from app.inspections.models import Inspection
from app.migrate import upgrade
from app.ops.requests import flush_logs
from app.stations.service import create_station
from app.trust.keys import forget_published_keys

TEST_DATABASE_ENV = "TRIKECERT_TEST_DATABASE_URL"
# This run's mark in the names of what it makes on a PostgreSQL server (its database and roles).
RUN = uuid.uuid4().hex[:12]
# What runs beside this one make on a shared server: `trikecert_<kind>_<12 hex digits>`.
_PER_RUN_NAME = re.compile(r"trikecert_[a-z_]+_([0-9a-f]{12})")


def pytest_configure(config: pytest.Config) -> None:
    """A PostgreSQL server URL naming a database the server lacks (a stock server has only
    `postgres`) connects to `postgres` instead: the URL only says where to make the run's database."""
    server_url = os.environ.get(TEST_DATABASE_ENV, "")
    if not server_url.startswith("postgresql"):
        return
    probe = create_engine(server_url)
    try:
        with probe.connect():
            pass
    except OperationalError as error:
        if "does not exist" not in str(error.orig):
            raise
        url = make_url(server_url).set(database="postgres")
        os.environ[TEST_DATABASE_ENV] = url.render_as_string(hide_password=False)
    finally:
        probe.dispose()


def _server_objects(server_url: str) -> set[str]:
    """Every role and database on the PostgreSQL server, as 'role NAME' and 'database NAME'."""
    engine = create_engine(server_url)
    try:
        with engine.connect() as connection:
            roles = connection.scalars(text("SELECT rolname FROM pg_roles"))
            found = {f"role {name}" for name in roles}
            databases = connection.scalars(text("SELECT datname FROM pg_database"))
            found |= {f"database {name}" for name in databases}
    finally:
        engine.dispose()
    return found


def _made_by_another_run(found: str) -> bool:
    named = _PER_RUN_NAME.fullmatch(found.split(" ", 1)[1])
    return named is not None and named[1] != RUN


@pytest.fixture(scope="session", autouse=True)
def _server_left_as_found() -> Iterator[None]:
    """On PostgreSQL, the run leaves the server's roles and databases as it found them (checked after
    every other fixture is torn down; what runs beside this one make meanwhile is theirs)."""
    server_url = os.environ.get(TEST_DATABASE_ENV, "")
    if not server_url.startswith("postgresql"):
        yield
        return
    before = _server_objects(server_url)
    yield
    left = sorted(f for f in _server_objects(server_url) - before if not _made_by_another_run(f))
    assert left == [], f"the run left these on the PostgreSQL server: {', '.join(left)}"


def pytest_collection(session: pytest.Session) -> None:
    """Before collecting (pytest has started): Hypothesis keeps each regex character class's strategy
    (tests/regex_classes.py), which tests/api/test_schemathesis.py builds while being collected."""
    keep_character_classes()


def pytest_collection_finish(session: pytest.Session) -> None:
    """What collecting the tests left (modules, the app's metadata, schemathesis's strategies: 600,000
    objects, none of them garbage) is moved out of the cyclic garbage collector's way, and the collector
    runs less often: the tests' own garbage is still freed, without walking all that again each time
    (tests/api and tests/certificates: 6.0 s of garbage collection in 7,441 passes, 3.4 s in 1,628)."""
    gc.collect()
    gc.freeze()
    gc.set_threshold(50_000, 20, 100)


@pytest.fixture(scope="session", autouse=True)
def _cheap_password_hashing() -> Iterator[None]:
    """Argon2 at its cheapest in the tests' process (tests/password_cost.py says why and where the
    production parameters are checked)."""
    with cheap_password_hashing():
        yield


@pytest.hookimpl(wrapper=True, trylast=True)
def pytest_runtest_setup(item: pytest.Item) -> Iterator[None]:
    """The access log's lines of the phase are written while its output is still captured."""
    try:
        return (yield)
    finally:
        flush_logs()


@pytest.hookimpl(wrapper=True, trylast=True)
def pytest_runtest_call(item: pytest.Item) -> Iterator[None]:
    """The access log's lines of the test are written while its output is still captured, never
    onto the terminal between tests (its thread writes them a moment after each request)."""
    try:
        return (yield)
    finally:
        flush_logs()


@pytest.hookimpl(wrapper=True, trylast=True)
def pytest_runtest_teardown(item: pytest.Item) -> Iterator[None]:
    """The access log's lines of the phase are written while its output is still captured."""
    try:
        return (yield)
    finally:
        flush_logs()


@pytest.fixture(scope="session")
def run_token() -> str:
    """This run's mark: a test that makes a role or database on the server puts it in its name."""
    return RUN


def _fresh_postgres(server_url: str) -> tuple[str, str]:
    """Create a new, empty database on the server; return its URL and name."""
    name = f"trikecert_test_{RUN}"
    admin = create_engine(server_url, isolation_level="AUTOCOMMIT")
    with admin.connect() as connection:
        connection.execute(text(f'CREATE DATABASE "{name}"'))
    admin.dispose()
    return make_url(server_url).set(database=name).render_as_string(hide_password=False), name


def _drop_postgres(server_url: str, name: str, role: str) -> None:
    admin = create_engine(server_url, isolation_level="AUTOCOMMIT")
    with admin.connect() as connection:
        connection.execute(text(f'DROP DATABASE IF EXISTS "{name}" WITH (FORCE)'))
        connection.execute(text(f'DROP ROLE IF EXISTS "{role}"'))  # its grants went with the database
    admin.dispose()


def _app_role_url(owner_url: str, role: str) -> str:
    """Make the run's app role on the fresh database; return the URL the app connects with."""
    password = secrets.token_urlsafe(18)
    owner = make_engine(owner_url)
    with owner.begin() as connection:
        grant_app_role(connection, role, password=password)
    owner.dispose()
    return make_url(owner_url).set(username=role, password=password).render_as_string(hide_password=False)


@pytest.fixture(scope="session")
def owner_url(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    """The URL of this run's fresh database as its owner, migrated to head."""
    server_url = os.environ.get(TEST_DATABASE_ENV, "")
    folder = Path(tmp_path_factory.mktemp("db"))
    if server_url.startswith("postgresql"):
        url, created = _fresh_postgres(server_url)
    else:
        url, created = f"sqlite:///{folder / 'trikecert-test.db'}", None
    os.environ["TRIKECERT_ENVIRONMENT"] = "test"
    # The run's signing key, held outside the database (on SQLite where it is by default, beside it).
    os.environ["TRIKECERT_SIGNING_KEY_FILE"] = str(folder / "trikecert-signing-key.pem")
    _clear_caches()
    owner = make_engine(url)
    upgrade(owner)
    owner.dispose()
    yield url
    if created:
        _drop_postgres(server_url, created, _run_role(created))


def _run_role(database: str) -> str:
    return database.replace("trikecert_test_", "trikecert_app_test_")


@pytest.fixture(scope="session")
def database_url(owner_url: str) -> Iterator[str]:
    """The URL the app connects with: the app role's on PostgreSQL, the same file on SQLite."""
    database = make_url(owner_url).database or ""
    is_postgres = owner_url.startswith("postgresql")
    url = _app_role_url(owner_url, _run_role(database)) if is_postgres else owner_url
    previous = os.environ.get("TRIKECERT_DATABASE_URL")
    os.environ["TRIKECERT_DATABASE_URL"] = url
    _clear_caches()
    yield url
    db.get_engine().dispose()
    _clear_caches()
    if previous is None:
        os.environ.pop("TRIKECERT_DATABASE_URL", None)
    else:
        os.environ["TRIKECERT_DATABASE_URL"] = previous


@pytest.fixture(scope="session")
def _postgres_owner_engine(owner_url: str) -> Iterator[Engine | None]:
    engine = make_engine(owner_url) if owner_url.startswith("postgresql") else None
    yield engine
    if engine is not None:
        engine.dispose()


@pytest.fixture
def owner_engine(database_url: str, _postgres_owner_engine: Engine | None) -> Engine:
    """An engine as the tables' owner (PostgreSQL: a superuser), for clean-up and faked history;
    on SQLite, which has no roles, the app's own engine."""
    return _postgres_owner_engine if _postgres_owner_engine is not None else db.get_engine()


def _clear_caches() -> None:
    config.get_settings.cache_clear()
    db.get_engine.cache_clear()
    db.get_sessionmaker.cache_clear()


@pytest.fixture
def engine(database_url: str, owner_engine: Engine) -> Iterator[Engine]:
    """The app's engine; every table is emptied by the owner after the test."""
    engine = db.get_engine()
    yield engine
    empty_every_table(owner_engine)
    # What a process keeps while the records say nothing changed: a database emptied and filled again
    # can say the same (ids restart, counts repeat), so the next test must not be served this one's.
    forget_bundles()
    forget_published_keys()
    forget_answers()


@pytest.fixture
def backdate(owner_engine: Engine) -> Callable[..., None]:
    """Rewrite a stored inspection's time (and other columns) as the owner: a test's faked history.

    The app cannot do this: inspections are append-only for its role and behind triggers.
    """

    def rewrite(inspection_id: int, at: datetime, **columns: object) -> None:
        with owner_engine.begin() as connection, immutability_lifted(connection, {Inspection.__tablename__}):
            connection.execute(
                update(Inspection).where(Inspection.id == inspection_id).values(created_at=at, **columns)
            )

    return rewrite


@pytest.fixture
def backdate_all(owner_engine: Engine) -> Callable[[Mapping[int, datetime]], None]:
    """Rewrite many stored inspections' times (id -> time) in one transaction as the owner."""

    def rewrite(times: Mapping[int, datetime]) -> None:
        rows = [{"inspection_id": key, "at": at} for key, at in times.items()]
        inspections = Inspection.metadata.tables[Inspection.__tablename__]
        statement = (
            update(inspections)
            .where(inspections.c.id == bindparam("inspection_id"))
            .values(created_at=bindparam("at"))
        )
        with owner_engine.begin() as connection, immutability_lifted(connection, {Inspection.__tablename__}):
            connection.execute(statement, rows)

    return rewrite


@pytest.fixture
def session(engine: Engine) -> Iterator[Session]:
    """A session on the run's database."""
    with db.get_sessionmaker()() as session:
        yield session


@pytest.fixture
def client(engine: Engine) -> Iterator[TestClient]:
    """A TestClient on the app of the current settings, as a fresh one would answer (no station key)."""
    with TestClient(application(), raise_server_exceptions=False) as client:
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
