"""Tests of the officer pages: HTTP tests with TestClient and browser tests with Chromium."""
