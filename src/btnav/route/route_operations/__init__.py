"""nav2_route's route operations, one per module (registered on import)."""
