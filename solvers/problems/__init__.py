"""One problem per body (issue 12): built from a config and a mesh, drives addressed per strip tag,
advance/ramp, named observables with units, fields for output.

* :mod:`.strip` — the LCE strip heated by its coil (current per coil tag; prescribed temperature or
  spontaneous-stretch fields).
* :mod:`.composite_beam` — the FE composite beam (lambda per strip tag; coil current through the
  heat model: :class:`~.composite_beam.HeatedBeamFE`).
* :mod:`.kapton_specimen` — the passive Kapton buckling specimen (end shortening).
* :mod:`.tension_specimen` — the LCE tension test in the isotropic phase.
* :mod:`.gridshell` — the FE gridshell (lambda per strip tag, group or channel).
* Bar-and-hinge: :mod:`.composite_beam_bh` (lambda_T, lambda_B ramp), :mod:`.kapton_specimen_bh`
  (end shortening, critical load), :mod:`.gridshell_bh` (lambda per strip, group or channel).
* :mod:`.twisted_ribbon` — the twisted LCE ribbon as a static 3D body under a prescribed temperature
  field (rod-like observables); the rolling ribbon on a hot plate is the Discrete Elastic Rod
  problem :mod:`lcefem.solvers.der.ribbon`.

docs/library.md shows how to script them.
"""
