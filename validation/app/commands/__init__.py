"""``lcefem run TARGET``: the command-line glue of each target, one module per target, imported only
when that target runs.

A module here holds argparse and printing only: the configuration classes, the problem, its time
loop or load path and its outputs are in lcefem.solvers.problems (run through the run skeleton,
lcefem.solvers.runtime.run.Run, and the writers of lcefem.solvers.exports); plots and comparisons
with measurements come from lcefem.validation and are handed to the run as a report hook.

Each module defines ``add_arguments(parser)`` (argparse; --out/--overwrite/--quiet from
lcefem.solvers.runtime.outdir.add_out_arguments), ``prepare(args)`` (the validated configuration,
before the output folder is claimed), ``main(args) -> int`` (runs the problem, prints one line) and,
when it cannot run under mpiexec, ``PARALLEL = False`` (or a function of args). Add a target by
registering its body (lcefem.solvers.registry.register, ``command`` the module's name).
"""

from lcefem.solvers.registry import targets


def parallel_if_fe(args) -> bool:
    """``PARALLEL`` of a target with a bar-and-hinge and an FE model: only the FE model runs under
    mpiexec (the bar-and-hinge model is serial numpy/scipy: every rank would write the same
    files)."""
    return args.model == "fe"


#: the --model choices of a target with both models
MODELS = ("bar-hinge", "fe")

#: ``lcefem run`` target -> its module, from the bodies' registrations
#: (lcefem.solvers.registry: one registration per body).
RUN_TARGETS = {
    target: f"lcefem.validation.app.commands.{module}" for target, module in targets().items()
}
