"""The estimates beyond the static test: vehicle figures, per-case estimates, their API, pages and PDF."""
