"""``lcefem run TARGET``: one module per target, imported only when that target runs.

Each module defines ``add_arguments(parser)`` (argparse; --out/--overwrite/--quiet from
lcefem.solvers.run.add_out_arguments), ``prepare(args)`` (the validated configuration, before the
output folder is claimed), ``main(args) -> int`` (runs through lcefem.solvers.run.Run) and, when it
cannot run under mpiexec, ``PARALLEL = False`` (or a function of args). Add a target by adding its module name here.
"""



def parallel_if_fe(args) -> bool:
    """``PARALLEL`` of a target with a bar-and-hinge and an FE model: only the FE model runs under
    mpiexec (the bar-and-hinge model is serial numpy/scipy: every rank would write the same files)."""
    return args.model == "fe"


RUN_TARGETS = {
    "ribbon": "lcefem.validation.runs.ribbon",
    "strip": "lcefem.validation.runs.strip",
    "beam": "lcefem.validation.runs.beam",
    "ribbon-buckling": "lcefem.validation.runs.ribbon_buckling",
    "gridshell": "lcefem.validation.runs.gridshell",
}
