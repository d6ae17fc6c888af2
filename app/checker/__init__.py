"""The offline checker: the /check page a phone installs, its scripts, service worker and manifest."""
