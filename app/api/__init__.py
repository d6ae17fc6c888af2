"""What every API route shares: error bodies, strict JSON, the body-size and per-address limits."""
