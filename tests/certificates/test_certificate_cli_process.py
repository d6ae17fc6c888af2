"""`trikecert` as an operator runs it, in its own process: a command that issues or revokes writes
its audit event as the service does (the database refuses a certificate with none)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path


def trikecert(folder: Path, *args: str) -> subprocess.CompletedProcess[str]:
    """Run the command line in a fresh interpreter, on a database of its own in `folder`."""
    environment = {
        **os.environ,
        "TRIKECERT_DATABASE_URL": f"sqlite:///{folder / 'trikecert.db'}",
        "TRIKECERT_SIGNING_KEY_FILE": str(folder / "signing.key"),
    }
    environment.pop("TRIKECERT_SIGNING_KEY", None)
    return subprocess.run(
        [sys.executable, "-m", "app.cli", *args],
        cwd=folder,
        env=environment,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )


def test_an_operator_issues_and_revokes_from_the_command_line(tmp_path: Path) -> None:
    demo = trikecert(tmp_path, "demo")
    assert demo.returncode == 0, demo.stderr
    issued = trikecert(tmp_path, "issue-certificate", "1")
    assert issued.returncode == 0, issued.stderr
    assert "TRK-" in issued.stdout
    number = next(word for word in issued.stdout.split() if word.startswith("TRK-")).rstrip(".:,")
    revoked = trikecert(tmp_path, "revoke-certificate", number, "--reason", "issued in error")
    assert revoked.returncode == 0, revoked.stderr
    assert number in revoked.stdout
    verified = trikecert(tmp_path, "audit-verify")
    assert verified.returncode == 0, verified.stdout + verified.stderr
