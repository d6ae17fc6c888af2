"""Feature phones and reminders (issue 23)."""
