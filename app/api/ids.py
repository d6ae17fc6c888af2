"""Record ids as path and query parameters of the API and the pages, bounded by app/ids.py's range
(the schema states the bounds; an id out of range is a 422 naming the parameter, before any query)."""

from __future__ import annotations

from typing import Annotated

from fastapi import Path, Query

from app.ids import MAX_ID

InspectionId = Annotated[
    int, Path(ge=1, le=MAX_ID, description="The inspection's id, as answered when it was stored.")
]
TypeAssessmentId = Annotated[
    int, Path(ge=1, le=MAX_ID, description="The type assessment's id, as answered when it was stored.")
]
StationId = Annotated[int, Path(ge=1, le=MAX_ID, description="The station's id.")]
UserId = Annotated[int, Path(ge=1, le=MAX_ID, description="The account's id.")]
PageNumber = Annotated[int, Query(ge=1, le=MAX_ID, description="Which page of the list, from 1.")]
# A filter's choice of record, where "" means "any": read as text, then by `app.ids.parse_id`.
IdChoice = Annotated[str, Query(description="A record's id, or empty for all.")]
