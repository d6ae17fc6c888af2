"""The sign-in lock-out holds under concurrency: a served app (real processes, two workers) gets 30
wrong passwords for one account at the same moment, then the right one."""

from __future__ import annotations

import os
import re
import ssl
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest
from served import free_port, wait_until_ready
from sqlalchemy import Engine, func, select
from sqlalchemy.orm import Session

from app.accounts.models import LoginAttempt
from app.config import get_settings

BIN = Path(sys.executable).parent
EMAIL = "racer@example.org"
PASSWORD = "a long passphrase for the race"
GUESSES = 30


@pytest.fixture
def served(engine: Engine, database_url: str, tmp_path: Path) -> Iterator[str]:
    """An officer account made with `trikecert create-user`, then `trikecert serve --workers 2`."""
    env = dict(os.environ, TRIKECERT_DATABASE_URL=database_url)
    subprocess.run(
        [BIN / "trikecert", "create-user", EMAIL, "--role", "officer", "--name", "Rita Racer"],
        input=PASSWORD + "\n",
        env=env,
        capture_output=True,
        text=True,
        check=True,
    )
    port = free_port()
    log = tmp_path / "server.log"
    with log.open("w") as output:
        server = subprocess.Popen(
            [BIN / "trikecert", "serve", "--no-migrate", "--port", str(port), "--workers", "2"],
            env=env,
            stdout=output,
            stderr=subprocess.STDOUT,
        )
    base = f"http://127.0.0.1:{port}"
    try:
        # Several answers in a row: past the start of both workers, not one that is still starting.
        wait_until_ready(f"{base}/readyz", server, timeout=120, in_a_row=4, log=log)
        yield base
    finally:
        server.terminate()
        server.wait(timeout=30)


def _login_form(base: str) -> tuple[dict[str, str], str]:
    """The sign-in page's cookie and form token, as a browser holds them."""
    page = httpx.get(f"{base}/login", timeout=10)
    token = re.search(r'name="csrf_token" value="([^"]+)"', page.text)
    assert token, page.text
    return dict(page.cookies), token[1]


def test_thirty_concurrent_wrong_passwords_check_no_more_than_the_limit_then_the_right_one_is_refused(
    served: str, session: Session
) -> None:
    cookies, token = _login_form(served)
    start = threading.Barrier(GUESSES)
    statuses: list[int] = []
    # One context for the thirty clients (the server is plain HTTP): each client would otherwise load
    # the CA bundle again, seconds of the test's CPU in all.
    context = ssl.create_default_context()

    def guess(n: int) -> None:
        with httpx.Client(cookies=cookies, timeout=60, verify=context) as browser:
            start.wait()
            form = {"email": EMAIL, "password": f"wrong guess {n}", "csrf_token": token}
            statuses.append(browser.post(f"{served}/login", data=form).status_code)

    threads = [threading.Thread(target=guess, args=(n,)) for n in range(GUESSES)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    time.sleep(0.3)
    with httpx.Client(cookies=cookies, timeout=60) as browser:
        right = browser.post(
            f"{served}/login", data={"email": EMAIL, "password": PASSWORD, "csrf_token": token}
        )

    limit = get_settings().login_max_failures
    assert right.status_code == 429, "the right password must not get in once the account is locked out"
    assert "too many failed sign-ins" in right.text
    checked = session.scalar(
        select(func.count()).where(LoginAttempt.email == EMAIL, LoginAttempt.outcome == "bad_credentials")
    )
    assert checked == limit == statuses.count(401)
    assert sorted(statuses) == [401] * limit + [429] * (GUESSES - limit)
