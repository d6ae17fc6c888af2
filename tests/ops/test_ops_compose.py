"""The compose file's app, started exactly as it says (command and environment), against the local
PostgreSQL in place of the `db` service, answers /readyz; its migration service migrates first, as
the owner, and sets up the app's own role, which can append to the records but never rewrite them."""

from __future__ import annotations

import os
import re
import secrets
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml
from served import free_port, wait_until_ready
from sqlalchemy import create_engine, text
from sqlalchemy.engine import make_url
from sqlalchemy.exc import DBAPIError

ROOT = Path(__file__).resolve().parents[2]
SERVER_URL = os.environ.get("TRIKECERT_TEST_DATABASE_URL", "")
pytestmark = pytest.mark.skipif(
    not SERVER_URL.startswith("postgresql"),
    reason="the compose stack runs on PostgreSQL: set TRIKECERT_TEST_DATABASE_URL",
)
_VARIABLE = re.compile(r"\$\{(\w+)(?::-([^}]*)|:\?[^}]*)?\}")


def interpolate(value: str, env: dict[str, str]) -> str:
    """Compose's ${VAR}, ${VAR:-default} and ${VAR:?message} substitution."""
    return _VARIABLE.sub(lambda m: env.get(m.group(1)) or (m.group(2) or ""), value)


def service(name: str) -> dict[str, Any]:
    """One service of docker-compose.yml."""
    compose = yaml.safe_load((ROOT / "docker-compose.yml").read_text())
    spec: dict[str, Any] = compose["services"][name]
    return spec


@pytest.fixture
def compose_env(run_token: str) -> Iterator[dict[str, str]]:
    """The variables compose would read from .env, and a fresh database standing in for `db`, owned
    by a role standing in for `trikecert` (the app's role, made by the migration, stands in for
    `trikecert_app`): the run's own names, all dropped afterwards, so the server is left as found."""
    password = secrets.token_urlsafe(16)
    name, owner, app = (
        f"trikecert_{kind}_{run_token}" for kind in ("compose", "compose_owner", "compose_app")
    )
    admin = create_engine(SERVER_URL, isolation_level="AUTOCOMMIT")
    server = make_url(SERVER_URL)
    try:
        with admin.connect() as connection:
            # The postgres image's POSTGRES_USER is a superuser: it may create the app's role.
            connection.execute(text(f'CREATE ROLE "{owner}" LOGIN SUPERUSER'))
            connection.execute(text(f'CREATE DATABASE "{name}" OWNER "{owner}"'))
        yield {
            "POSTGRES_PASSWORD": password,
            "TRIKECERT_APP_DB_PASSWORD": secrets.token_urlsafe(16),
            "TRIKECERT_BASE_URL": "https://trikecert.example.gov",
            "TRIKECERT_WORKERS": "2",
            "_DB": name,
            "_HOST": server.host or "127.0.0.1",
            "_PORT": str(server.port or 5432),
            "_ROLES": f"trikecert={owner},trikecert_app={app}",
        }
    finally:
        with admin.connect() as connection:
            connection.execute(text(f'DROP DATABASE IF EXISTS "{name}" WITH (FORCE)'))
            connection.execute(text(f'DROP ROLE IF EXISTS "{app}"'))  # its grants went with the database
            connection.execute(text(f'DROP ROLE IF EXISTS "{owner}"'))
        admin.dispose()


def roles_of(env: dict[str, str]) -> dict[str, str]:
    """The compose file's role names -> the roles standing in for them here."""
    return dict(pair.split("=", 1) for pair in env["_ROLES"].split(","))


def environment_of(name: str, env: dict[str, str]) -> dict[str, str]:
    """The service's environment as compose would set it, with `db:5432/trikecert` and its roles
    pointed here."""
    roles = roles_of(env)
    result = dict(os.environ)
    result.pop("TRIKECERT_DATABASE_URL", None)
    for key, value in service(name)["environment"].items():
        result[key] = interpolate(str(value), env)
    url = make_url(result["TRIKECERT_DATABASE_URL"])
    assert (url.host, url.port, url.database) == ("db", 5432, "trikecert"), url
    result["TRIKECERT_DATABASE_URL"] = url.set(
        username=roles[url.username or ""], host=env["_HOST"], port=int(env["_PORT"]), database=env["_DB"]
    ).render_as_string(hide_password=False)
    if "TRIKECERT_APP_DB_ROLE" in result:
        result["TRIKECERT_APP_DB_ROLE"] = roles[result["TRIKECERT_APP_DB_ROLE"]]
    result["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{result['PATH']}"
    return result


def command_of(name: str, env: dict[str, str]) -> list[str]:
    """The service's command, interpolated."""
    return [interpolate(part, env) for part in service(name)["command"]]


def test_the_app_and_the_migration_connect_as_two_roles() -> None:
    owner = make_url(service("migrate")["environment"]["TRIKECERT_DATABASE_URL"]).username
    app = make_url(service("app")["environment"]["TRIKECERT_DATABASE_URL"]).username
    assert owner == service("db")["environment"]["POSTGRES_USER"]
    assert app == service("migrate")["environment"]["TRIKECERT_APP_DB_ROLE"] != owner
    for name in ("migrate", "app"):
        assert service(name)["environment"]["TRIKECERT_BASE_URL"].startswith("${TRIKECERT_BASE_URL:?")


def assert_the_app_role_cannot_rewrite_records(env: dict[str, str]) -> None:
    """As the app's URL says: reading works, rewriting an inspection or a certificate does not."""
    engine = create_engine(environment_of("app", env)["TRIKECERT_DATABASE_URL"])
    try:
        for sql in (
            "UPDATE inspection SET front_kg = 0",
            "DELETE FROM certificate",
            "TRUNCATE loading_case",
            "ALTER TABLE certificate DISABLE TRIGGER ALL",
        ):
            with (
                engine.connect() as connection,
                pytest.raises(DBAPIError, match=r"permission denied|must be owner"),
            ):
                connection.execute(text(sql))
        with engine.connect() as connection:
            assert connection.scalar(text("SELECT count(*) FROM inspection")) == 0
    finally:
        engine.dispose()


def test_the_compose_app_starts_as_written_and_is_ready(compose_env: dict[str, str]) -> None:
    migrate = subprocess.run(
        command_of("migrate", compose_env),
        env=environment_of("migrate", compose_env),
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert migrate.returncode == 0, migrate.stderr
    assert f"app role {roles_of(compose_env)['trikecert_app']}" in migrate.stdout
    assert_the_app_role_cannot_rewrite_records(compose_env)

    port = free_port()
    command = [part.replace("--port 8000", f"--port {port}") for part in command_of("app", compose_env)]
    assert f"--port {port}" in command[-1], "the compose command no longer names --port 8000"
    app = subprocess.Popen(
        command,
        env=environment_of("app", compose_env),
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
    )
    try:
        body = wait_until_ready(f"http://127.0.0.1:{port}/readyz", app)  # a 200, or it fails
        assert app.poll() is None, app.stdout.read().decode() if app.stdout else "the app exited"
        assert body == '{"status":"ok"}'
    finally:
        app.terminate()
        app.wait(timeout=30)
