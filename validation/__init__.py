"""The users' work: cases, reference data with sources, convergence studies, plots, reports, CLI."""
