"""The composition root's parts: every capability's routers in the order they are matched, and the
callbacks lower packages are handed so that no package imports one above it (docs/architecture.md).

Importing this module wires those callbacks; app/main.py mounts the routers.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from fastapi import APIRouter

from app.accounts.admin_views import router as admin_router
from app.accounts.deps import offers_navigation
from app.accounts.second_factor_views import router as second_factor_router
from app.accounts.views import router as accounts_router
from app.api.errors import UNAVAILABLE_RESPONSE
from app.audit_log.api import router as audit_api_router
from app.audit_log.views import router as audit_router
from app.certificates.api import router as certificates_api_router
from app.certificates.api import verify_certificate
from app.certificates.public import trust_bundle
from app.certificates.views import verify_page
from app.checker.views import router as checker_router
from app.dynamics.api import router as dynamics_api_router
from app.dynamics.lookups import find_vehicles_with, get_inspections_with
from app.dynamics.views import router as vehicle_dynamics_router
from app.gateway.africastalking import router as africastalking_router
from app.inspections.api import router as inspections_api_router
from app.inspections.api import submission_router
from app.inspections.home import router as home_router
from app.inspections.service import count_matches_with, get_inspection
from app.inspections.views import router as inspections_router
from app.notifications.views import router as reminders_router
from app.pages.inspection import router as inspection_page_router
from app.pages.vehicle import router as vehicle_page_router
from app.remedies.api import router as remedies_api_router
from app.stations.views import router as stations_router
from app.statistics.matching import count_matching_inspections
from app.statistics.views import router as statistics_router
from app.type_assessments.api import router as type_assessments_api_router
from app.type_assessments.views import router as type_assessments_router
from app.vehicles.api import router as vehicles_api_router
from app.vehicles.service import display_registration, find_vehicle
from app.vehicles.views import router as vehicles_router
from app.web.templating import use_navigation_rule

# The station API under /api/v1.
api_router = APIRouter(prefix="/api/v1", responses=UNAVAILABLE_RESPONSE)
# A weighing's submission first: the route stations call most is matched before any other.
hot_router = APIRouter(prefix="/api/v1", responses=UNAVAILABLE_RESPONSE)
hot_router.include_router(submission_router)
api_router.include_router(vehicles_api_router)
api_router.include_router(inspections_api_router)
api_router.include_router(remedies_api_router)
api_router.include_router(dynamics_api_router)
api_router.include_router(certificates_api_router)
api_router.include_router(audit_api_router)
api_router.include_router(type_assessments_api_router)

# The routes whose kept answers app/certificates/kept_door.py serves ahead of the router, by kind:
# the request log names them as if they had answered.
kept_endpoints: dict[str, Callable[..., Any]] = {
    "verify-html": verify_page,
    "verify-json": verify_page,
    "api-verify": verify_certificate,
    "bundle": trust_bundle,
}

# The officer pages (app/web/setup.py mounts them).
page_routers: tuple[APIRouter, ...] = (
    home_router,
    accounts_router,
    second_factor_router,
    admin_router,
    audit_router,
    stations_router,
    vehicle_dynamics_router,
    vehicles_router,
    vehicle_page_router,
    inspections_router,
    inspection_page_router,
    statistics_router,
    type_assessments_router,
    reminders_router,
    checker_router,  # the offline checker at /check/: the one page with scripts
)

# The SMS and USSD gateway's callbacks (app/gateway/): plain text in and out, outside the station API.
callback_routers: tuple[APIRouter, ...] = (africastalking_router,)

# The layout offers its navigation once a session has passed its second factor (accounts decide).
use_navigation_rule(offers_navigation)
# A list of inspections counts the closed days it covers from the statistics' stored counts.
count_matches_with(count_matching_inspections)
# The vehicle figures page finds its vehicle, and the dynamics endpoint its inspection, through the
# packages above app/dynamics/ (which use its figures and estimates).
find_vehicles_with(find_vehicle, display_registration)
get_inspections_with(get_inspection)
