"""Registered tricycles and their seat layouts."""
