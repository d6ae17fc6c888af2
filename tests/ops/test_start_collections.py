"""A process of the app (a command, a served worker, a test run) starts without the garbage collector
walking everything imported so far again and again (a tenth of `import app.main`), and a served worker
goes back to the collector's thresholds once it has frozen what it holds (app/__init__.py,
app.main.create_served_app)."""

from __future__ import annotations

import json
import subprocess
import sys
from typing import Any

IMPORTED = """
import gc, json
found = gc.get_threshold()
import app.main
full_collections = gc.get_stats()[2]["collections"]
app.main.create_served_app()
print(json.dumps({"found": found, "full_collections": full_collections,
                  "served": gc.get_threshold(), "frozen": gc.get_freeze_count()}))
"""


def _started() -> dict[str, Any]:
    """What a fresh process found, did while importing the app, and kept once it serves."""
    run = subprocess.run([sys.executable, "-c", IMPORTED], capture_output=True, text=True, check=True)
    started: dict[str, Any] = json.loads(run.stdout)
    return started


def test_importing_the_app_runs_no_full_collection_and_a_served_worker_goes_back_to_the_thresholds() -> None:
    started = _started()
    assert started["full_collections"] == 0, "importing the app walked every object again"
    assert started["served"] == started["found"], "the served worker kept the start's thresholds"
    assert started["frozen"] > 100_000, "the worker froze too little"
