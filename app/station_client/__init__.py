"""The station client: what a weighbridge station's PC runs to deliver weighings exactly once.

Weighings are read from a CSV or JSON file or a weighing indicator's serial output, queued on disk
first (a small SQLite file, each with its own Idempotency-Key), then sent with retries and backoff
until the service has answered each one. Nothing is lost or sent twice across a restart.
"""
