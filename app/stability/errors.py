"""Domain errors of the stability core."""


class StabilityError(ValueError):
    """A refused input: names the field, the rule it broke and what to do instead."""

    def __init__(self, field: str, rule: str, message: str) -> None:
        super().__init__(message)
        self.field = field
        self.rule = rule
        self.message = message

    def __repr__(self) -> str:
        return f"StabilityError(field={self.field!r}, rule={self.rule!r}, message={self.message!r})"
