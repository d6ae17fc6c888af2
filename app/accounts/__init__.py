"""Officers and administrators: accounts, roles and passwords."""
