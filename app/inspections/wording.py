"""TEMPORARY (until w-moves is merged): the moved modules still import the words from here."""

from app.wording import *  # noqa: F403
