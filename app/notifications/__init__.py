"""Reminders before a certificate runs out: subscriptions confirmed by their contact, an outbox written
in the same transaction as the decision to send, and the worker that delivers it (docs/notifications.md)."""
