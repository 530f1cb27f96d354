"""Controllers (MPPI, DWB, Regulated Pure Pursuit), goal and progress checkers."""
