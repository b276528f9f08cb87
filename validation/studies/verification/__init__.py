"""Verification: manufactured solutions, the rod's closed forms, the grid convergence index."""
