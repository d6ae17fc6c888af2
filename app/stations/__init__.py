"""Weighbridge stations and their API credentials."""
