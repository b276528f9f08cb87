"""The application: the ``lcefem`` command line, its commands, case files, the farm, the report."""
