"""The `uma` command: sub-commands discovered from `uma/cli/cmd_*.py`.

Each `cmd_NAME.py` module defines `register(subparsers)`, which adds its parser and sets
`func=handler` with `handler(args) -> int`. Modules here import only the standard library at the
top; the work they call is imported inside the handler, so `uma --help` stays instant.
Errors: an `UmaError` becomes one line `uma: error: ...` and its exit code (2 bad input, 1 a
problem the run found); anything else is a bug and keeps its traceback.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import sys
from collections.abc import Sequence

__all__ = ["main", "build_parser"]

DESCRIPTION = """\
Simulate a video conference streamed to a roaming mobile user. A UMA engine adapts H.264
(bit rate, resolution, frame rate) to the receiver's downlink, which follows a real bandwidth
trace across WLAN, 3G, GPRS and GSM, and falls back to a model-based face codec when the
bandwidth collapses. Results go to results/<scenario>/ (metrics.json, frames.csv, events.csv).

Start with `uma run` (the default Stockholm-Uppsala scenario), then `uma run --help`."""


def _command_modules(prefix: str) -> list[str]:
    import uma.cli as pkg

    return sorted(m.name for m in pkgutil.iter_modules(pkg.__path__) if m.name.startswith(prefix))


def build_parser() -> argparse.ArgumentParser:
    """The full parser, with every `cmd_*` sub-command registered."""
    from uma.cli.args import OneLineParser

    parser = OneLineParser(
        prog="uma",
        description=DESCRIPTION,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=_version())
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in _command_modules("cmd_"):
        importlib.import_module(f"uma.cli.{name}").register(sub)
    return parser


def _version() -> str:
    from uma import __version__

    return f"uma {__version__}"


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status.

    Ctrl-C at any moment, imports and parsing included, is one line and exit 130. A reader of
    stdout that went away (`uma bench ... --json | head`) ends the command quietly with exit 1,
    as Python's documentation advises for SIGPIPE, instead of a traceback.
    """
    try:
        return _main(argv)
    except KeyboardInterrupt:
        print("uma: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # Python flushes stdout again at exit, which would fail the same way: point it at null.
        import os

        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 1


def _main(argv: Sequence[str] | None) -> int:
    from uma.errors import UmaError
    from uma.interrupt import loading

    try:
        with loading():
            parser = build_parser()
            args = parser.parse_args(argv)  # a bad option is a ConfigError (`OneLineParser`)
        if not getattr(args, "func", None):
            parser.print_help()
            return 2
        return int(args.func(args) or 0)
    except UmaError as err:
        print(f"uma: error: {err}", file=sys.stderr)
        return err.exit_code


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
