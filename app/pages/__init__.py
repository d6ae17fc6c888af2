"""The pages that show several capabilities side by side (a vehicle, an inspection): each gathers
what the capabilities' services and views give, above them all."""
