"""nav2_route's edge cost functions, one per module (registered on import)."""
