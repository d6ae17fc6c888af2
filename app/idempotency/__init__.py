"""Idempotency-Key on the station API's POSTs: a retried request is answered once, never stored twice."""
