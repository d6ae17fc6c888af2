"""Inspections: one weighing session of one vehicle, its readings and its loading cases."""
