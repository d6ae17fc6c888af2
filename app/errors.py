"""Domain errors that carry their HTTP status, shared by every door (API, pages, CLI)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class FieldProblem:
    """One refused field: where, which rule, and what to do."""

    field: str
    rule: str
    message: str


class ServiceError(Exception):
    """A refusal the user can act on; `status` is the HTTP status the API answers with."""

    status = 400

    def __init__(self, message: str, *, field: str | None = None, rule: str = "invalid") -> None:
        super().__init__(message)
        self.message = message
        self.problems = [FieldProblem(field, rule, message)] if field else []


class InvalidInput(ServiceError):
    """The input breaks a rule of the domain (422)."""

    status = 422


class NotFound(ServiceError):
    """The thing asked for does not exist (404)."""

    status = 404


class Conflict(ServiceError):
    """The request clashes with what is stored, such as a duplicate registration (409)."""

    status = 409
