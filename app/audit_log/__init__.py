"""The audit log read back: its pages and API, the chain verified, signed checkpoints of its head.

The events themselves are written by app/audit/ (the recorder on every session's flush).
"""
