"""The ``lcefem`` command line: ``lcefem run TARGET ...``, ``lcefem validate``, ``lcefem converge``.

Bad input prints one line ``lcefem: error: ...`` naming the field and what is allowed, and exits 2.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from lcefem.models.errors import ConvergenceError, InputError
from lcefem.validation.runs import RUN_TARGETS

EXIT_INPUT = 2
EXIT_CONVERGENCE = 3


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # argparse's own errors: one line, exit 2
        self.exit(EXIT_INPUT, f"{self.prog}: error: {message}\n")


def build_parser(argv: list[str] | None = None) -> argparse.ArgumentParser:
    """The full parser; with ``argv`` naming a run target, only that target's module is imported
    (targets that need no FEniCSx then start without importing it)."""
    parser = _Parser(prog="lcefem", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    run = sub.add_parser("run", help="run one simulation")
    targets = run.add_subparsers(dest="target", required=True, parser_class=_Parser,
                                 metavar="{" + ",".join(RUN_TARGETS) + "}")
    wanted = list(RUN_TARGETS)
    if argv and len(argv) >= 2 and argv[0] == "run" and argv[1] in RUN_TARGETS:
        wanted = [argv[1]]
    elif argv and argv[0] in ("validate", "converge"):
        wanted = []  # other commands need no run-target modules
    for name in wanted:
        mod = importlib.import_module(RUN_TARGETS[name])
        p = targets.add_parser(name, help=(mod.__doc__ or "").strip().splitlines()[0])
        mod.add_arguments(p)
        p.set_defaults(_main=mod.main)
    for name in ("validate", "converge"):
        module = f"lcefem.validation.{name}"
        try:
            mod = importlib.import_module(module)
        except ModuleNotFoundError as exc:
            if exc.name != module:
                raise
            continue
        p = sub.add_parser(name, help=(mod.__doc__ or "").strip().splitlines()[0])
        mod.add_arguments(p)
        p.set_defaults(_main=mod.main)
    return parser


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser(argv)
    args = parser.parse_args(argv)
    try:
        return int(args._main(args) or 0)
    except InputError as exc:
        print(f"lcefem: error: {exc}", file=sys.stderr)
        return EXIT_INPUT
    except ConvergenceError as exc:
        print(f"lcefem: stopped: {exc}", file=sys.stderr)
        return EXIT_CONVERGENCE
    except KeyboardInterrupt:
        print("lcefem: interrupted; partial outputs keep their .part names", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
