"""Tests of the pages in each language trikecert speaks."""
