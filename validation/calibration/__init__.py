"""Calibration scripts: each reruns a fit and writes its result and residuals under validation/data/."""
