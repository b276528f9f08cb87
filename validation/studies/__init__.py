"""The studies, one folder per topic: what the cases and commands compute beyond a body's run."""
