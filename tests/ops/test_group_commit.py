"""Group commit on SQLite (app/group_commit.py): writes that wait for the writer's turn while another
holds it are written and committed together, each caller answered only once its rows are durable,
and a write that fails in a batch fails alone. On a SQLite file of the test's own, whichever
database the run uses."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from sqlalchemy import Connection, Engine, event, text
from sqlalchemy.exc import IntegrityError

from app.db import make_engine
from app.group_commit import commit_group, write_and_commit

FOLLOWERS = 5


@pytest.fixture
def engine(tmp_path: Path) -> Iterator[Engine]:
    """A SQLite file with one table of notes, each body once."""
    engine = make_engine(f"sqlite:///{tmp_path / 'group.db'}")
    with engine.begin() as connection:
        connection.execute(text("CREATE TABLE note (id INTEGER PRIMARY KEY, body TEXT NOT NULL UNIQUE)"))
    yield engine
    engine.dispose()


def insert(body: str) -> Callable[[Connection], int]:
    def write(connection: Connection) -> int:
        return int(
            connection.execute(
                text("INSERT INTO note (body) VALUES (:b) RETURNING id"), {"b": body}
            ).scalar_one()
        )

    return write


def stored(engine: Engine) -> dict[str, int]:
    with engine.connect() as connection:
        return {body: id_ for id_, body in connection.execute(text("SELECT id, body FROM note"))}


def commits(engine: Engine) -> list[int]:
    """A list that grows by one at every COMMIT on the engine."""
    seen: list[int] = []
    event.listen(engine, "commit", lambda _connection: seen.append(1))
    return seen


def behind_a_held_turn(
    engine: Engine, bodies: list[str]
) -> tuple[dict[str, int | BaseException], dict[str, bool]]:
    """The leader writes 'first' and holds the turn until every body of `bodies` is queued behind it,
    each on a thread and a connection of its own; what each got, and whether its row was readable
    by another connection the moment its call returned."""
    inside, release = threading.Event(), threading.Event()
    results: dict[str, int | BaseException] = {}
    durable: dict[str, bool] = {}

    def held(connection: Connection) -> int:
        value = insert("first")(connection)
        inside.set()  # the leader holds the turn, its batch taken
        assert release.wait(timeout=30), "the followers never queued"
        return value

    def run(body: str, write: Callable[[Connection], int]) -> None:
        try:
            with engine.connect() as connection:
                results[body] = write_and_commit(connection, write)
        except BaseException as error:  # the test reads it back
            results[body] = error
            return
        durable[body] = body in stored(engine)

    leader = threading.Thread(target=run, args=("first", held))
    leader.start()
    assert inside.wait(timeout=30)
    followers = [threading.Thread(target=run, args=(body, insert(body))) for body in bodies]
    for follower in followers:
        follower.start()
    deadline = time.monotonic() + 30
    while commit_group(engine).waiting < len(bodies) and time.monotonic() < deadline:
        time.sleep(0.01)
    release.set()
    for thread in [leader, *followers]:
        thread.join(timeout=30)
    return results, durable


def test_writes_queued_behind_the_turn_are_committed_together_each_with_its_own_result(
    engine: Engine,
) -> None:
    seen = commits(engine)
    bodies = [f"note {i}" for i in range(FOLLOWERS)]
    results, durable = behind_a_held_turn(engine, bodies)
    rows = stored(engine)
    assert results == rows, "every write stored, each caller given its own row's id"
    assert set(rows) == {"first", *bodies}
    assert len(seen) == 2, "the leader's commit, then one for the five that waited"
    assert durable == dict.fromkeys(["first", *bodies], True), "no caller answered before its commit"


def test_a_write_that_fails_in_a_batch_fails_alone(engine: Engine) -> None:
    bodies = ["note 1", "first", "note 2", "note 3"]  # 'first' is stored already by the leader
    results, _durable = behind_a_held_turn(engine, bodies)
    rows = stored(engine)
    assert set(rows) == {"first", "note 1", "note 2", "note 3"}
    assert isinstance(results.pop("first"), IntegrityError), "the duplicate gets its own error"
    assert results == {body: rows[body] for body in ("note 1", "note 2", "note 3")}


def test_one_write_alone_is_committed_at_once(engine: Engine) -> None:
    seen = commits(engine)
    with engine.connect() as connection:
        new_id = write_and_commit(connection, insert("alone"))
        with pytest.raises(IntegrityError):
            write_and_commit(connection, insert("alone"))
    assert stored(engine) == {"alone": new_id}
    assert len(seen) == 1
