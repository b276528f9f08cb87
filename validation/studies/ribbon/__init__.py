"""Studies of the rolling twisted ribbon (seed 000)."""
