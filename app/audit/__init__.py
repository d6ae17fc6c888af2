"""The tamper-evident record of who did what: every change to an account, station, vehicle, signing
key or certificate, and every sign-in, as one hash-chained audit event."""
