"""Apply Alembic migrations from code (used by `trikecert migrate`, `serve` and the tests)."""

from __future__ import annotations

from pathlib import Path

from alembic import command
from alembic.config import Config
from alembic.runtime.migration import MigrationContext
from alembic.script import ScriptDirectory
from sqlalchemy import Engine
from sqlalchemy.exc import DBAPIError

import migrations
from app.config import get_settings
from app.errors import ServiceError
from app.grants import grant_app_role

INSUFFICIENT_PRIVILEGE = "42501"


class NotTheOwner(ServiceError):
    """The role connected may not change the schema (the app's role): migrate as the owner."""


def alembic_config(url: str) -> Config:
    """An Alembic config pointing at the packaged migrations and the given database."""
    config = Config()
    config.set_main_option("script_location", str(Path(migrations.__file__).parent))
    config.set_main_option("sqlalchemy.url", url.replace("%", "%%"))
    return config


def upgrade(engine: Engine) -> str | None:
    """Bring the database to the newest revision; grant TRIKECERT_APP_DB_ROLE its rights, in the same
    transaction (PostgreSQL). Returns the role granted, if any."""
    settings = get_settings()
    role = settings.app_db_role if engine.dialect.name == "postgresql" else None
    config = alembic_config(engine.url.render_as_string(hide_password=False))
    try:
        with engine.begin() as connection:
            config.attributes["connection"] = connection
            command.upgrade(config, "head")
            if role is not None:
                password = settings.app_db_password
                grant_app_role(connection, role, password=password.get_secret_value() if password else None)
    except DBAPIError as error:
        if getattr(error.orig, "sqlstate", None) != INSUFFICIENT_PRIVILEGE:
            raise
        raise NotTheOwner(
            f"the database role {engine.url.username} may not change the schema ({error.orig}); "
            "run `trikecert migrate` as the owner of the tables, and `serve --no-migrate` as the app role"
        ) from error
    return role


def is_at_head(engine: Engine) -> bool:
    """True when the database carries the newest revision."""
    script = ScriptDirectory.from_config(alembic_config(str(engine.url)))
    with engine.connect() as connection:
        current = set(MigrationContext.configure(connection).get_current_heads())
    return current == set(script.get_heads())
