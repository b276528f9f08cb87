"""One problem per body (issue 12): built from a config and a mesh, drives addressed per strip tag,
advance/ramp, named observables with units, fields for output."""
