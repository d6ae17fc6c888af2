"""Type (model-level) assessments: several vehicles of one make and model, stored for good."""
