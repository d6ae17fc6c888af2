"""Write the OpenAPI document and the HTML of every officer and public page to a folder, so that two
checkouts can be compared byte for byte (a restructuring must change none of them).

    .venv/bin/python tools/snapshot_pages.py OUT_DIR

It builds a fresh SQLite database in a temporary folder, loads the demo, adds an administrator, an
officer's second inspection, a certificate, a refusal, a type assessment and dynamics figures through
the pages themselves, then fetches every page. What differs from run to run whatever the code (form
tokens, the signed QR payloads and their pictures, clock times) is replaced by a placeholder; nothing
else is touched.
"""

from __future__ import annotations

import base64
import os
import re
import sys
import tempfile
from pathlib import Path

_TOKEN = re.compile(r'name="(csrf_token|form_token)" value="[^"]*"')
_VOLATILE = [
    (_TOKEN, r'name="\1" value="TOKEN"'),
    (re.compile(r"\b\d{4}-\d{2}-\d{2}[T ]\d{2}:\d{2}:\d{2}(\.\d+)?(Z|[+-]\d{2}:?\d{2})?"), "TIMESTAMP"),
    (re.compile(r"\b[0-9a-f]{64}\b"), "HASH"),
    (re.compile(r"\b[0-9a-f]{32}\b"), "REQUEST"),
    (re.compile(r"/[vV]/[0-9A-Z$%*+\-./: ]{20,}"), "/V/PAYLOAD"),
    (re.compile(r"HC1:[0-9A-Z$%*+\-./: ]+"), "HC1:PAYLOAD"),
    (re.compile(r"<svg[^>]*class=\"qr[^\"]*\"[\s\S]*?</svg>"), "<svg QR/>"),
    (re.compile(r"data:image/(png|svg\+xml);base64,[A-Za-z0-9+/=]+"), "data:image/IMAGE"),
    (re.compile(r"\b\d{2}:\d{2}(:\d{2})?( UTC)?\b"), "HH:MM"),
    (re.compile(r"otpauth://[^\"'<\s]+"), "otpauth://SECRET"),
    (re.compile(r"\b[A-Z2-7]{32}\b"), "BASE32SECRET"),
    (re.compile(r"tks?_[A-Za-z0-9_\-]+"), "tk_KEY"),
    (re.compile(r'<svg[^>]*class="segno"[\s\S]*?</svg>'), "<svg QR/>"),
]


PASSWORD = "correct horse battery"  # noqa: S105  (a throwaway account in a throwaway database)


def normalised(text: str) -> str:
    """The page with what differs between runs of the same code replaced by placeholders."""
    for pattern, replacement in _VOLATILE:
        text = pattern.sub(replacement, text)
    return text


def main(out: Path) -> int:
    """Build the data, fetch every page, write each to OUT_DIR; return the exit status."""
    folder = Path(tempfile.mkdtemp(prefix="trikecert-snapshot-"))
    os.environ["TRIKECERT_DATABASE_URL"] = f"sqlite:///{folder / 'snapshot.db'}"
    os.environ["TRIKECERT_ENVIRONMENT"] = "test"
    # One fixed key (a seed of zeros): the key's id and the signatures are the same in every run.
    os.environ["TRIKECERT_SIGNING_KEY"] = base64.b64encode(bytes(32)).decode()
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

    from fastapi.testclient import TestClient
    from web.webtools import code_at, enrol, hidden, post_form, sign_in  # noqa: F401

    from app import db
    from app.accounts.service import create_user
    from app.config import get_settings
    from app.demo import load_demo
    from app.main import create_app
    from app.migrate import upgrade

    upgrade(db.get_engine())
    with db.get_sessionmaker()() as session:
        demo = load_demo(session, get_settings())
        assert demo.inspection is not None
        inspection_id = demo.inspection.id
        create_user(session, email="admin@example.org", password=PASSWORD, role="admin", name="Ada")
        session.commit()

    out.mkdir(parents=True, exist_ok=True)
    pages: dict[str, str] = {}
    with TestClient(create_app(), raise_server_exceptions=False) as client:
        pages["openapi.json"] = client.get("/openapi.json").text  # as served: key order is part of it
        for name, url in [("login", "/login"), ("verify-form", "/verify")]:
            pages[name] = client.get(url).text
        assert sign_in(client, "admin@example.org", PASSWORD).status_code == 303
        issue = client.get(f"/inspections/{inspection_id}")
        refusal = client.post(
            f"/inspections/{inspection_id}/certificate",
            data={"csrf_token": hidden(issue.text)},
            follow_redirects=False,
        )
        number = refusal.headers.get("location", "/certificates/none").rsplit("/", 1)[-1]
        urls = {
            "home": "/",
            "find": "/vehicles/find",
            "find-plate": "/vehicles/find?registration=BDG252QH",
            "register": "/vehicles/new",
            "vehicle": "/vehicles/BDG252QH",
            "vehicle-dynamics": "/vehicles/BDG252QH/dynamics",
            "new-inspection": "/vehicles/BDG252QH/inspections/new",
            "inspection": f"/inspections/{inspection_id}",
            "inspection-remedies": f"/inspections/{inspection_id}?target_occupants=4&ballast_x_m=1.5",
            "inspections": "/inspections",
            "certificate": f"/certificates/{number}",
            "verify-number": f"/verify/{number}",
            "verify-unknown": "/verify/TRK-2026-999999-X",
            "statistics": "/statistics",
            "statistics-csv": "/statistics.csv",
            "users": "/admin/users",
            "new-user": "/admin/users/new",
            "stations": "/admin/stations",
            "new-station": "/admin/stations/new",
            "station": "/admin/stations/1",
            "settings": "/admin/settings",
            "audit": "/admin/audit",
            "audit-csv": "/admin/audit.csv",
            "two-factor": "/account/two-factor",
            "type-assessment-new": "/type-assessments/new",
            "not-found": "/vehicles/NOPE000",
            "keys": "/.well-known/trikecert-keys.json",
            "verify-api": f"/api/v1/verify/{number}",
        }
        for name, url in urls.items():
            answer = client.get(url)
            pages[name] = f"{answer.status_code}\n{answer.text}"
        for name, page_url, fields in [
            ("register-errors", "/vehicles/new", {"registration_number": "", "wheelbase_m": "-1"}),
            ("inspection-errors", "/vehicles/BDG252QH/inspections/new", {"front_kg": "-5"}),
            ("station-errors", "/admin/stations/new", {"name": ""}),
        ]:
            answer = post_form(client, page_url, page_url, fields)
            pages[name] = f"{answer.status_code}\n{answer.text}"
    for name, text in pages.items():
        (out / f"{name}.html" if not name.endswith(".json") else out / name).write_text(normalised(text))
    print(f"{len(pages)} pages written to {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(Path(sys.argv[1])))
