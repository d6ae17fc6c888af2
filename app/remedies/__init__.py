"""What would make a vehicle comply: remedies sized from the stored readings, their API shape and page."""
