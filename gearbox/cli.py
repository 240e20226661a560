"""The ``gearbox`` console script: one command, verbs as sub-commands.

Each verb lives in ``gearbox/commands/<verb>.py`` with ``HELP``, ``EXAMPLES``,
``add_arguments(parser)`` and ``run(args) -> int``. Verb modules import nothing heavy
at module level, so ``gearbox --help`` stays fast.

Exit status: 0 success, 2 invalid input (message on stderr, no traceback), 1 other
failure.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from . import __version__
from .errors import InputError

#: verb -> module; the order is the order of ``--help``.
VERBS = {
    "run": "gearbox.commands.run",
    "design": "gearbox.commands.design",
    "sweep": "gearbox.commands.sweep",
    "simulate": "gearbox.commands.simulate",
    "modes": "gearbox.commands.modes",
    "fmu": "gearbox.commands.fmu",
    "cosim": "gearbox.commands.cosim",
    "tca": "gearbox.commands.tca",
    "ltca": "gearbox.commands.ltca",
    "scene-doc": "gearbox.commands.scene_doc",
}

EPILOG = """examples:
  gearbox run models/marine_drive.toml         the whole job: report in out/marine_drive/
  gearbox design models/case03.toml            readable design table and checks
  gearbox design models/case03.toml --json     the same as one JSON object
  gearbox sweep models/case03.toml --out out/  parameter studies (paper Figs. 6-9)
  gearbox tca models/case03.toml --out out/    unloaded contact paths, TE, FPD angles
  gearbox modes models/case03.toml --json      drivetrain eigenfrequencies and modes
  gearbox <verb> --help                        options of one verb
"""


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="gearbox",
        description="Crossed beveloid gear pairs: design, contact analysis, mesh tables, drivetrain vibration.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"gearbox {__version__}")
    sub = parser.add_subparsers(dest="verb", metavar="VERB")
    for verb, modname in VERBS.items():
        mod = importlib.import_module(modname)
        p = sub.add_parser(
            verb,
            help=mod.HELP,
            description=mod.HELP,
            epilog="examples:\n" + mod.EXAMPLES,
            formatter_class=argparse.RawDescriptionHelpFormatter,
        )
        mod.add_arguments(p)
        p.set_defaults(_module=mod)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.verb is None:
        parser.print_help()
        return 2
    try:
        return int(args._module.run(args) or 0)
    except InputError as exc:
        print(f"gearbox {args.verb}: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"gearbox {args.verb}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # the reader of the output left (``gearbox design X | head``): stop quietly, as
        # other command-line tools do; point stdout at devnull so that the interpreter's
        # final flush does not fail again (Python docs, "Note on SIGPIPE")
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141


def console() -> None:
    """The ``gearbox`` command: :func:`main`, then leave at once.

    Once the command's files are written and closed and its worker processes have
    ended, the process exits without the interpreter's teardown of every loaded module
    (with jax, scipy and matplotlib loaded that teardown measured 0.3 s on a 2-core
    machine). Under a profiler or tracer (``python -m cProfile``, coverage,
    whatever way it watches) the normal exit is kept, so that they can write their
    results. An exception that leaves :func:`main` takes the normal way out, with its
    traceback."""
    code = main()
    watched = sys.getprofile() is not None or sys.gettrace() is not None
    if watched or "coverage" in sys.modules:  # coverage may watch through sys.monitoring
        sys.exit(code)
    from .commands._common import exit_now

    exit_now(code)


if __name__ == "__main__":  # pragma: no cover
    console()
