"""Certificates: numbered, immutable, signed records of one inspection's verdict, with their PDF."""

from app.certificates import guard as guard  # registers the ORM's refusal to change certified rows
