"""Numerics: heat, mechanics, coupled stepping, continuation, and the reduced-order integrators.

Solvers take model objects and meshes; they know nothing of experiments.
"""
