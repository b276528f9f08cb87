"""Studies of the composite beam (seed 001, Fig. 3)."""
