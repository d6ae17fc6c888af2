"""Administrator pages: list accounts, add one, change its name and badge, disable or enable it,
set a new password."""

from __future__ import annotations

from fastapi import APIRouter
from starlette.requests import Request
from starlette.responses import RedirectResponse, Response

from app.accounts.deps import AdminLogin, AdminPost, ConfirmedAdminPost
from app.accounts.names import person_on_page
from app.accounts.service import (
    MAX_PASSWORD_LENGTH,
    ROLES,
    create_user,
    get_user,
    list_users,
    set_password,
    set_user_active,
    set_user_details,
)
from app.accounts.sessions import set_flash
from app.api.ids import UserId
from app.errors import ServiceError
from app.i18n.active import gettext as _
from app.i18n.active import pgettext
from app.web.deps import FormDep, SessionDep
from app.web.forms import FormErrors, secret, text
from app.web.templating import render

router = APIRouter(prefix="/admin/users", include_in_schema=False)
NEW_USER_INPUTS = {
    "email": "email",
    "name": "name",
    "badge": "badge",
    "role": "role-officer",
    "password": "password",
}


def role_name(role: str) -> str:
    """The role as a page names it, in the active language (the stored value stays English)."""
    return pgettext("role", "admin") if role == "admin" else pgettext("role", "officer")


@router.get("")
def users_page(request: Request, session: SessionDep, login: AdminLogin) -> Response:
    """Every account with its role and status."""
    return render(request, "accounts/users.html", {"users": list_users(session)})


@router.get("/new")
def new_user_form(request: Request, login: AdminLogin) -> Response:
    """The form to add an account."""
    return render(request, "accounts/user_new.html", {"values": {"role": "officer"}, "roles": ROLES})


@router.post("/new")
def add_user(request: Request, session: SessionDep, login: ConfirmedAdminPost, form: FormDep) -> Response:
    """Create the account (it grants a role, so the admin proves who they are again after five
    minutes), or show the form again with the problems."""
    errors = FormErrors()
    values = {
        "email": text(form, "email", errors, limit=254),
        "name": text(form, "name", errors, limit=1000),  # the service refuses a long one, never cuts it
        "badge": text(form, "badge", errors, limit=1000),
        "role": text(form, "role", errors, limit=16),
    }
    password = secret(form, "password", errors, limit=MAX_PASSWORD_LENGTH)
    if "role" in errors.messages:  # the role is a radio button: its message goes beside the first one
        errors.messages["role-officer"] = errors.messages.pop("role")
    status = 422
    if not errors:
        try:
            user = create_user(
                session,
                email=values["email"],
                password=password,
                role=values["role"],
                name=values["name"],
                badge=values["badge"],
            )
        except ServiceError as error:
            errors.add_problems(error.problems, NEW_USER_INPUTS, "email")
            status = error.status if error.status != 409 else 422
    if errors:
        return render(
            request,
            "accounts/user_new.html",
            {"values": values, "errors": errors.messages, "roles": ROLES},
            status_code=status,
        )
    set_flash(
        session,
        login,
        _("Account %(email)s (%(role)s) created.") % {"email": user.email, "role": role_name(user.role)},
    )
    return RedirectResponse("/admin/users", status_code=303)


@router.get("/{user_id}/edit")
def details_form(request: Request, session: SessionDep, login: AdminLogin, user_id: UserId) -> Response:
    """The form to change an account's name and badge number."""
    account = get_user(session, user_id)
    values = {"name": account.display_name or "", "badge": account.badge_number or ""}
    return render(request, "accounts/user_edit.html", {"account": account, "values": values})


@router.post("/{user_id}/edit")
def save_details(
    request: Request, session: SessionDep, login: AdminPost, form: FormDep, user_id: UserId
) -> Response:
    """Save the name and badge number, or show the form again with the problem."""
    account = get_user(session, user_id)
    errors = FormErrors()
    values = {
        "name": text(form, "name", errors, limit=1000),
        "badge": text(form, "badge", errors, limit=1000),
    }
    if not errors:
        try:
            set_user_details(session, user=account, name=values["name"], badge=values["badge"])
        except ServiceError as error:
            session.rollback()
            errors.add_problems(error.problems, {"name": "name", "badge": "badge"}, "name")
    if errors:
        return render(
            request,
            "accounts/user_edit.html",
            {"account": account, "values": values, "errors": errors.messages},
            status_code=422,
        )
    set_flash(
        session,
        login,
        _("%(email)s is now shown as %(name)s.") % {"email": account.email, "name": person_on_page(account)},
    )
    return RedirectResponse("/admin/users", status_code=303)


@router.post("/{user_id}/disable")
def disable_user(session: SessionDep, login: AdminPost, user_id: UserId) -> Response:
    """Disable an account and end its sessions (never your own)."""
    user = get_user(session, user_id)
    if user.id == login.user_id:
        set_flash(session, login, _("You cannot disable your own account."))
    else:
        set_user_active(session, user=user, active=False)
        set_flash(
            session,
            login,
            _("%(email)s is disabled and has been signed out everywhere.") % {"email": user.email},
        )
    return RedirectResponse("/admin/users", status_code=303)


@router.post("/{user_id}/enable")
def enable_user(session: SessionDep, login: AdminPost, user_id: UserId) -> Response:
    """Enable an account again."""
    user = set_user_active(session, user=get_user(session, user_id), active=True)
    set_flash(session, login, _("%(email)s can sign in again.") % {"email": user.email})
    return RedirectResponse("/admin/users", status_code=303)


@router.get("/{user_id}/password")
def password_form(request: Request, session: SessionDep, login: AdminLogin, user_id: UserId) -> Response:
    """The form to set a new password for an account."""
    return render(request, "accounts/user_password.html", {"account": get_user(session, user_id)})


@router.post("/{user_id}/password")
def reset_password(
    request: Request, session: SessionDep, login: ConfirmedAdminPost, form: FormDep, user_id: UserId
) -> Response:
    """Set the new password and end the account's other sessions."""
    user = get_user(session, user_id)
    errors = FormErrors()
    password = secret(form, "password", errors, limit=MAX_PASSWORD_LENGTH)
    if not errors:
        try:
            set_password(session, user=user, password=password, keep_session_id=login.id)
        except ServiceError as error:
            errors.add_problems(error.problems, {"password": "password"}, "password")
    if errors:
        return render(
            request,
            "accounts/user_password.html",
            {"account": user, "errors": errors.messages},
            status_code=422,
        )
    set_flash(
        session,
        login,
        _("New password set for %(email)s; their other sessions have ended.") % {"email": user.email},
    )
    return RedirectResponse("/admin/users", status_code=303)
