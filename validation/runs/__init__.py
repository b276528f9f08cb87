"""``lcefem run TARGET``: one module per target, imported only when that target runs.

Each module defines ``add_arguments(parser)`` (argparse) and ``main(args) -> int``. Add a target by
adding its module name here.
"""

RUN_TARGETS = {
    "ribbon": "lcefem.validation.runs.ribbon",
    "strip": "lcefem.validation.runs.strip",
    "beam": "lcefem.validation.runs.beam",
    "ribbon-buckling": "lcefem.validation.runs.ribbon_buckling",
}
