"""The station API under /api/v1."""

from fastapi import APIRouter

from app.api.errors import UNAVAILABLE_RESPONSE
from app.audit.api import router as audit_router
from app.certificates.api import router as certificates_router
from app.dynamics.api import router as dynamics_router
from app.inspections.api import router as inspections_router
from app.inspections.api import submission_router
from app.type_assessments.api import router as type_assessments_router
from app.vehicles.api import router as vehicles_router

api_router = APIRouter(prefix="/api/v1", responses=UNAVAILABLE_RESPONSE)
# A weighing's submission first: the route stations call most is matched before any other.
hot_router = APIRouter(prefix="/api/v1", responses=UNAVAILABLE_RESPONSE)
hot_router.include_router(submission_router)
api_router.include_router(vehicles_router)
api_router.include_router(inspections_router)
api_router.include_router(dynamics_router)
api_router.include_router(certificates_router)
api_router.include_router(audit_router)
api_router.include_router(type_assessments_router)
