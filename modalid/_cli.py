"""The shared runner of the project's command-line tools."""

from __future__ import annotations

import argparse
import sys

__all__ = ["run_command", "add_fit_options", "fit_options", "add_read_options", "read_options",
           "in_flags"]

# Python argument words in library messages -> the command line's flags
_FLAGS = (("passive=False", "--driving-point no"), ("passive=True", "--driving-point yes"),
          ("passive='auto'", "--driving-point auto"),
          ("format='complex-lines'", "--format complex-lines"), ("freq_hz=", "--freq-start/--df"),
          ("quantity=", "--quantity"), ("index=", "--index"), ("format=", "--format"),
          ("freq_range", "--fmin/--fmax"), ("window_decay_rate", "--window-decay"),
          ("record_length", "--record-length"), ("missed_modes", "--missed-modes"),
          ("weighting=", "--weighting"), ("n_modes", "--n-modes"))


def in_flags(message: str) -> str:
    """``message`` with the Python argument names it mentions replaced by the flags."""
    for word, flag in _FLAGS:
        message = message.replace(word, flag)
    return message


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
        print(f"{parser.prog}: error: {in_flags(str(exc))}", file=sys.stderr)
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


def add_read_options(parser: argparse.ArgumentParser) -> None:
    """How an FRF file is read: ``--quantity``, ``--index``, ``--format`` and, for bare
    complex lines, ``--freq-start``/``--df``."""
    parser.add_argument("--quantity", choices=("receptance", "mobility", "accelerance"),
                        help="the FRF's quantity if the file does not say it")
    parser.add_argument("--index", type=int, default=None,
                        help="which FRF of a multi-FRF file")
    parser.add_argument("--format", default=None,
                        choices=("csv", "npz", "mat", "uff", "complex-lines"),
                        help="the file's format (default: from its extension and content)")
    parser.add_argument("--freq-start", type=float, default=None, metavar="HZ",
                        help="a complex-lines file: the frequency of its first line (Hz)")
    parser.add_argument("--df", type=float, default=None, metavar="HZ",
                        help="a complex-lines file: the spacing of its lines (Hz)")


def read_options(args, path) -> dict:
    """The ``read_frf`` keyword arguments of :func:`add_read_options`'s options; the line
    frequencies of a complex-lines file from ``--freq-start`` and ``--df``."""
    import numpy as np

    options = {"quantity": args.quantity, "index": args.index, "format": args.format}
    if args.df is not None or args.freq_start is not None:
        if args.df is None or not args.df > 0:
            raise ValueError(f"--df must be a positive line spacing (Hz), got {args.df!r}")
        with open(path) as stream:
            n_lines = sum(1 for line in stream if line.strip())
        start = 0.0 if args.freq_start is None else args.freq_start
        options["freq_hz"] = start + args.df * np.arange(n_lines)
        options["format"] = "complex-lines"
    return {k: v for k, v in options.items() if v is not None}