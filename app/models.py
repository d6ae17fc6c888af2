"""Imports every ORM model so the metadata is complete (for Alembic and the tests)."""

import app.audited  # noqa: F401  (the audit listener on every session, told which records to follow)
from app.accounts.models import LoginAttempt, LoginThrottle, RecoveryCode, User, UserSession
from app.audit.models import AuditEvent
from app.certificates.models import (
    Certificate,
    CertificateAudit,
    CertificateRevocation,
    CertificateSequence,
)
from app.db import Base
from app.dynamics.models import VehicleDynamicsRevision
from app.idempotency.models import IdempotencyKey
from app.inspections.models import Inspection, LoadingCaseRow, Reading
from app.stations.models import Station, StationRateWindow
from app.statistics.models import StatisticsDay, StatisticsDayStation
from app.trust.models import KeyEndorsement, KeyGrandfathered, KeyWithdrawal, SigningKey
from app.type_assessments.models import TypeAssessmentCase, TypeAssessmentInspection, TypeAssessmentRecord
from app.vehicles.models import Seat, Vehicle
from app.web.models import FormSubmission

__all__ = [
    "AuditEvent",
    "Base",
    "Certificate",
    "CertificateAudit",
    "CertificateRevocation",
    "CertificateSequence",
    "FormSubmission",
    "IdempotencyKey",
    "Inspection",
    "KeyEndorsement",
    "KeyGrandfathered",
    "KeyWithdrawal",
    "LoadingCaseRow",
    "LoginAttempt",
    "LoginThrottle",
    "Reading",
    "RecoveryCode",
    "Seat",
    "SigningKey",
    "Station",
    "StationRateWindow",
    "StatisticsDay",
    "StatisticsDayStation",
    "TypeAssessmentCase",
    "TypeAssessmentInspection",
    "TypeAssessmentRecord",
    "User",
    "UserSession",
    "Vehicle",
    "VehicleDynamicsRevision",
]
