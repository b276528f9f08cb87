"""Geometry only: gmsh builders returning meshes with named tags, one module per body."""
