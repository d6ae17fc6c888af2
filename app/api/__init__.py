"""What every API route shares: error bodies, the body-size limit, the /api/v1 router."""
