"""The shared runner of the project's command-line tools."""

from __future__ import annotations

import argparse
import sys

__all__ = ["run_command", "add_fit_options", "fit_options"]


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


def add_fit_options(parser: argparse.ArgumentParser) -> None:
    """The ``ModalFit`` options of the commands that fit FRF files: the mode search and an
    exponential window (``--missed-modes``, ``--window-decay``, ``--record-length``)."""
    parser.add_argument("--missed-modes", choices=("strict", "dense"), default="strict",
                        help="dense: the fit adds every mode the residual and the "
                             "information criterion support (bands with many weak or close "
                             "modes)")
    parser.add_argument("--window-decay", type=float, default=None, metavar="RATE",
                        help="the FRFs carry an exponential window exp(-RATE t) (1/s): the "
                             "fit models it and the models are without it")
    parser.add_argument("--record-length", type=float, default=None, metavar="T",
                        help="length (s) of the records behind the FRFs (no zero padding): "
                             "the fit undoes the record's end too")


def fit_options(args) -> dict:
    """The ``ModalFit`` keyword arguments of :func:`add_fit_options`'s options (only those
    given or not at their default)."""
    options = {}
    if args.missed_modes != "strict":
        options["missed_modes"] = args.missed_modes
    if args.window_decay is not None:
        options["window_decay_rate"] = args.window_decay
    if args.record_length is not None:
        options["record_length"] = args.record_length
    return options
