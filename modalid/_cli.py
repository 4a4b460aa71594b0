"""The shared runner of the project's command-line tools."""

from __future__ import annotations

import argparse
import sys

__all__ = ["run_command"]


def run_command(parser: argparse.ArgumentParser, argv=None, *,
                errors=(ValueError, TypeError, FileNotFoundError)) -> int:
    """Parse ``argv``, run the chosen sub-command's ``func``; bad input exits 2 with a message.

    Expected errors (bad values, missing files) are reported on one line without a
    traceback; anything else propagates, since it is a bug.
    """
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 0
    try:
        return args.func(args)
    except errors as exc:
        print(f"{parser.prog}: error: {exc}", file=sys.stderr)
        return 2
