"""Which records the audit log follows, and how each appears in it: the composition root tells the
recorder (app/audit/recorder.py), which knows no capability's models."""

from __future__ import annotations

from typing import Any

from app.accounts.models import LoginAttempt, User
from app.audit.recorder import Audited, audit
from app.certificates.models import Certificate, CertificateRevocation
from app.dynamics.models import DYNAMICS_FIELDS, VehicleDynamicsRevision
from app.stations.models import Station
from app.trust.models import SigningKey
from app.type_assessments.models import TypeAssessmentRecord
from app.vehicles.models import Vehicle


def _issued(record: Any) -> str:
    return ("refusal" if record.kind == "refusal" else "certificate") + ".issued"


FOLLOWED: dict[type[Any], Audited] = {
    User: Audited(
        "user", ("email", "role", "active"), lambda r: r.id, frozenset({"password_hash", "totp_secret"})
    ),
    Station: Audited("station", ("name", "active"), lambda r: r.id, frozenset({"key_hash"})),
    Vehicle: Audited("vehicle", ("registration_number", "make", "model"), lambda r: r.registration_number),
    VehicleDynamicsRevision: Audited(
        "vehicle",
        ("revision", *DYNAMICS_FIELDS, "seat_heights_m"),
        lambda r: r.vehicle.registration_number,
        created_action=lambda _r: "vehicle.dynamics_recorded",
    ),
    SigningKey: Audited("signing_key", ("kid", "source", "active"), lambda r: r.kid),
    Certificate: Audited(
        "certificate",
        ("kind", "registration_number", "inspection_id", "second_language"),
        lambda r: r.number,
        created_action=_issued,
        event_first=True,
    ),
    CertificateRevocation: Audited(
        "certificate",
        ("reason",),
        lambda r: r.certificate.number,
        created_action=lambda _r: "certificate.revoked",
        event_first=True,
    ),
    LoginAttempt: Audited(
        "user", ("email", "client_ip"), lambda r: r.user_id, created_action=lambda r: f"sign_in.{r.outcome}"
    ),
    TypeAssessmentRecord: Audited(
        "type_assessment", ("make", "model", "model_year", "vehicle_count", "compliant"), lambda r: r.id
    ),
}
for _model, _audited in FOLLOWED.items():
    audit(_model, _audited)
