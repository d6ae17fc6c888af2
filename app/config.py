"""Settings from the environment (prefix TRIKECERT_), read once and cached."""

from __future__ import annotations

import ipaddress
from decimal import Decimal
from functools import lru_cache
from pathlib import Path
from typing import Literal
from urllib.parse import urlsplit

from pydantic import Field, SecretStr, ValidationError, field_validator, model_validator
from pydantic_settings import BaseSettings, SettingsConfigDict
from sqlalchemy.engine import make_url

from app.grants import check_role_name
from app.i18n.locales import ENGLISH, LOCALES
from app.stability import Rules

# The languages a paper may be printed in besides English (which is always first, and binding).
SECOND_LANGUAGES = tuple(locale for locale in LOCALES if locale != ENGLISH)
PLACEHOLDER_SECRETS = {
    "",
    "changeme",
    "change-me",
    "password",
    "postgres",
    "secret",
    "placeholder",
    "trikecert",
}


class Settings(BaseSettings):
    """Every knob of the service; each one can be set as TRIKECERT_<NAME> in the environment."""

    model_config = SettingsConfigDict(env_prefix="TRIKECERT_", env_file=".env", extra="ignore")

    environment: Literal["development", "test", "production"] = "development"
    database_url: str = "sqlite:///./trikecert.db"
    # PostgreSQL: the role the service connects as. `trikecert migrate`, run as the tables' owner with
    # these set, creates it if missing (with this password) and grants it only what the app does.
    app_db_role: str | None = None
    app_db_password: SecretStr | None = None
    occupant_mass_kg: Decimal = Field(default=Decimal("72"), ge=20, le=250)
    sum_tolerance: Decimal = Field(default=Decimal("0.01"), gt=0, le=Decimal("0.1"))
    # Beyond the static test (estimates only): air density for drag, and a regulator's minimum
    # rollover threshold drawn on the stability map (unset: no line).
    air_density_kg_m3: float = Field(default=1.2, gt=0, le=2)
    min_rollover_g: float | None = Field(default=None, gt=0, le=2)
    max_body_bytes: int = 1024 * 1024
    page_size: int = Field(default=50, ge=1, le=500)
    session_idle_minutes: int = 30
    session_absolute_hours: int = 12
    login_max_failures: int = 5
    login_lockout_minutes: int = 15
    # Failed checks one client address may make within the lock-out period before it waits too: far
    # above one account's allowance, since carrier-grade NAT puts many officers behind one address.
    login_address_max_failures: int = Field(default=100, ge=1)
    # The second factor at sign-in: "required" of every account, or "optional" (used where enrolled).
    # Unset: required in production, optional in development and tests.
    mfa: Literal["required", "optional"] | None = None
    cookie_secure: bool = False
    certificate_validity_months: int = Field(default=12, ge=1, le=120)
    # The public address printed on certificates and in QR codes; production requires an https one.
    base_url: str = "http://127.0.0.1:8000"
    issuing_authority: str = "Tricycle Lateral Stability Certification Authority"
    # The language printed under the English on a certificate or refusal unless the officer picks
    # another when issuing it: ha, yo, ig or pcm; empty: English only (the English stays binding).
    paper_second_language: str = ""
    # Where the Ed25519 key that signs QR payloads and audit checkpoints is held: never in the database.
    # A PEM file (0600) the service reads and rotation rewrites; unset: trikecert-signing-key.pem beside
    # the SQLite database file, else in the working directory (made on first use).
    signing_key_file: Path | None = None
    # Or a PKCS#11 token (an HSM; SoftHSM2 for tests and small sites): the module's library, the token's
    # label and user PIN, and the label of the key pair on it. Set the module to use the token.
    pkcs11_module: Path | None = None
    pkcs11_token_label: str = "trikecert"  # noqa: S105 (a label, not a secret)
    pkcs11_pin: SecretStr | None = None
    pkcs11_key_label: str = Field(default="trikecert-signing", min_length=1, max_length=64)
    # Or the key itself (PEM, base64 of PEM, or base64 of the 32-byte seed); rotated by changing it.
    signing_key: SecretStr | None = None
    # Pages show times and count "today" in this zone; everything is stored in UTC.
    display_timezone: str = "Africa/Lagos"
    # Where the remedies place front ballast unless asked otherwise: metres behind the front wheel
    # centre (negative: ahead of it, a bumper or a battery tray).
    ballast_x_m: Decimal = Field(default=Decimal("0.30"), ge=-1, le=5, decimal_places=4)
    # Weighbridge stations: settling of repeated readings, scale calibration, rate limit, idempotency keys.
    max_reading_spread_kg: Decimal = Field(default=Decimal("2"), gt=0, le=100)
    require_calibration: bool = False  # refuse stations with no calibration on record
    station_rate_limit: int = Field(default=120, ge=0)  # requests per station key per window; 0: off
    station_rate_window_seconds: int = Field(default=60, ge=1, le=3600)
    # Keys no station holds, per client address and window: beyond the limit 429 (valid keys still pass).
    bad_key_limit: int = Field(default=20, ge=0)  # 0: off
    bad_key_window_seconds: int = Field(default=300, ge=1, le=3600)
    # The public verification (/verify, /V/, /api/v1/verify, the published keys): requests per client
    # address and window, far above a police post's use, far below an enumeration of the register.
    public_rate_limit: int = Field(default=300, ge=0)  # 0: off
    public_rate_window_seconds: int = Field(default=60, ge=1, le=3600)
    # The trust bundle (/.well-known/trikecert-trust): after made_at + this many hours an offline checker
    # refuses to decide ("Cannot confirm: connect to update the list").
    trust_max_age_hours: int = Field(default=72, ge=1, le=24 * 30)
    # The key ids `trikecert verify --offline` and `trikecert trust-bundle --from` trust a bundle signed
    # by (comma-separated; each is a thumbprint of its public key), besides any --anchor given.
    trust_anchors: str = ""
    # Slow clients: a request's headers, then its body, must each arrive whole within these seconds.
    header_timeout_seconds: float = Field(default=10, gt=0, le=300)
    body_timeout_seconds: float = Field(default=30, gt=0, le=600)
    idempotency_key_hours: int = Field(default=24, ge=24, le=24 * 90)
    # Requests one app process handles at once (the threads that run the routes), and the database
    # connections it keeps open: one per request in flight, so a pool as large as the threads is never
    # short and never opens and closes connections under load. Overflow is a safety margin only.
    worker_threads: int = Field(default=16, ge=1, le=200)
    db_pool_size: int = Field(default=16, ge=1, le=200)
    db_max_overflow: int = Field(default=4, ge=0, le=200)
    # /metrics answers only `Authorization: Bearer <token>`; unset: off (404) in production, open otherwise.
    metrics_token: SecretStr | None = Field(default=None, min_length=16)
    # Proxies whose X-Forwarded-Proto/-For uvicorn believes (IPs or networks, comma-separated; "*": any).
    forwarded_allow_ips: str = ""
    # Feature phones and reminders (docs/notifications.md). The gateway's callbacks are answered only
    # with ?token=<this> in their URL; unset: the callbacks are off (404).
    gateway_callback_token: SecretStr | None = Field(default=None, min_length=16)
    # And, when set, only from these addresses or networks (comma-separated).
    gateway_allowed_ips: str = ""
    # Africa's Talking's send API: its base address (the sandbox's, or a local one in tests), the
    # account's username and API key, and the sender id or short code messages come from.
    africastalking_base_url: str = "https://api.africastalking.com"
    africastalking_username: str = "sandbox"
    africastalking_api_key: SecretStr | None = None
    africastalking_sender: str | None = None
    # The country code a phone number written without one belongs to (0801... -> +234801...).
    phone_country_code: str = Field(default="234", pattern=r"^[1-9][0-9]{0,2}$")
    # Where reminders by email go out: smtp://user:password@host:587 (STARTTLS when offered) or
    # smtps://... (TLS from the start); unset: no email is sent (messages wait in the outbox).
    smtp_url: SecretStr | None = None
    mail_from: str = "trikecert <reminders@trikecert.invalid>"
    # The key of the contacts' digests (HMAC; docs/notifications.md); unset: a file of random bytes
    # beside the signing key file, made on first use.
    contact_digest_key: SecretStr | None = Field(default=None, min_length=32)
    # Limits: confirmation codes per contact and per client address a day; checks per phone an hour.
    confirmations_per_contact: int = Field(default=3, ge=1)
    confirmations_per_address: int = Field(default=20, ge=1)
    checks_per_phone: int = Field(default=30, ge=1)
    # The worker: seconds between passes, one send's timeout, attempts before a message is given up.
    notify_interval_seconds: float = Field(default=30, gt=0, le=3600)
    notify_timeout_seconds: float = Field(default=10, gt=0, le=120)
    notify_max_attempts: int = Field(default=8, ge=1, le=50)
    # Sent and failed messages (their text; the recipient is erased at once) are deleted after this.
    notify_keep_days: int = Field(default=30, ge=1, le=3650)

    @field_validator(
        "gateway_callback_token",
        "africastalking_api_key",
        "africastalking_sender",
        "smtp_url",
        "contact_digest_key",
        mode="before",
    )
    @classmethod
    def blank_is_unset(cls, value: object) -> object:
        """An empty variable (as docker-compose passes an unset one) means unset."""
        return None if value == "" else value

    @field_validator("paper_second_language")
    @classmethod
    def check_paper_second_language(cls, value: str) -> str:
        """Empty (English only) or a language the papers are printed in besides English."""
        value = value.strip().lower()
        if value in ("", ENGLISH):
            return ""
        if value not in SECOND_LANGUAGES:
            raise ValueError(
                f"{value!r} is not a paper language; leave it empty for English only, or set one of "
                + ", ".join(SECOND_LANGUAGES)
            )
        return value

    @field_validator("gateway_allowed_ips")
    @classmethod
    def check_gateway_allowed_ips(cls, value: str) -> str:
        """Each entry an IP address or network."""
        entries = [entry.strip() for entry in value.split(",") if entry.strip()]
        for entry in entries:
            try:
                ipaddress.ip_network(entry, strict=False)
            except ValueError:
                raise ValueError(f"{entry!r} is not an IP address or network") from None
        return ",".join(entries)

    @field_validator("forwarded_allow_ips")
    @classmethod
    def check_forwarded_allow_ips(cls, value: str) -> str:
        """Each entry an IP address or network, or "*"."""
        return ",".join(trusted_proxies(value))

    @field_validator("app_db_role")
    @classmethod
    def plain_role_name(cls, role: str | None) -> str | None:
        """The app role is a plain lower-case identifier (it is written into GRANT statements)."""
        return None if role is None or role == "" else check_role_name(role)

    @model_validator(mode="after")
    def refuse_placeholder_secrets(self) -> Settings:
        """Outside development and tests, a database password must be a real secret."""
        if self.environment == "production":
            password = make_url(self.database_url).password
            if password is not None and _placeholder(password):
                raise ValueError(
                    "TRIKECERT_DATABASE_URL: the database password is a placeholder or shorter than 12 "
                    "characters; set a real secret in production"
                )
            if self.app_db_password is not None and _placeholder(self.app_db_password.get_secret_value()):
                raise ValueError(
                    "TRIKECERT_APP_DB_PASSWORD: the app role's password is a placeholder or shorter than "
                    "12 characters; set a real secret in production"
                )
        return self

    @model_validator(mode="after")
    def refuse_a_made_up_public_address(self) -> Settings:
        """In production the address printed on every certificate is given, and it is https."""
        if self.environment != "production":
            return self
        example = "set it to the service's public https address, e.g. https://trikecert.example.gov"
        if "base_url" not in self.model_fields_set:
            raise ValueError(f"TRIKECERT_BASE_URL is not set; {example} (it is printed in every QR code)")
        parts = urlsplit(self.base_url)
        if parts.scheme != "https" or not parts.hostname or parts.query or parts.fragment:
            raise ValueError(f"TRIKECERT_BASE_URL {self.base_url!r} is not an https address; {example}")
        return self

    def mfa_mode(self) -> Literal["required", "optional"]:
        """The second factor in force: as set, else required in production and optional elsewhere."""
        if self.mfa is not None:
            return self.mfa
        return "required" if self.environment == "production" else "optional"

    def rules(self) -> Rules:
        """The stability rules in force under these settings."""
        return Rules(occupant_mass_kg=self.occupant_mass_kg, sum_tolerance=self.sum_tolerance)


def _placeholder(secret: str) -> bool:
    return len(secret) < 12 or secret.lower() in PLACEHOLDER_SECRETS


def settings_problems(error: ValidationError) -> list[str]:
    """One plain line per refused setting, naming its TRIKECERT_ variable (for a start-up message)."""
    lines = []
    for problem in error.errors():
        message = str(problem["msg"]).removeprefix("Value error, ")
        field = ".".join(str(part) for part in problem["loc"])
        lines.append(f"TRIKECERT_{field.upper()}: {message}" if field else message)
    return lines


def trusted_proxies(value: str) -> list[str]:
    """The entries of TRIKECERT_FORWARDED_ALLOW_IPS; a ValueError names the first that is no IP or network."""
    entries = [entry.strip() for entry in value.split(",") if entry.strip()]
    for entry in entries:
        if entry != "*":
            try:
                ipaddress.ip_network(entry)  # strict, as uvicorn reads it
            except ValueError:
                raise ValueError(
                    f"TRIKECERT_FORWARDED_ALLOW_IPS: {entry!r} is not an IP address or network"
                ) from None
    return entries


@lru_cache
def get_settings() -> Settings:
    """The process-wide settings (tests clear the cache to change them)."""
    return Settings()
