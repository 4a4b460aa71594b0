"""The shared ground of the project's command-line tools (``modalid``, ``impactpred``).

One runner (:func:`run_command`: one-line errors, exit status 2), the identification
options of every command that fits FRF files (:func:`add_fit_options`,
:func:`fit_options`), the options that say how an FRF file is read
(:func:`add_read_options`, :func:`read_options`), the check of an output folder given
with ``--out`` (:func:`check_out_dir`), and the one translation of the library's Python
argument names into the flags that set them (:func:`in_flags`).
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

__all__ = ["run_command", "add_fit_options", "fit_options", "add_read_options", "read_options",
           "in_flags", "check_out_dir", "nothing_saved", "window_line", "uff_reading",
           "record_reading"]

#: phrases whose value picks the flag (matched first, as written)
_PHRASES = (("check_passive=False", "--no-passivity-check"),
            ("continuation=False", "--no-continuation"),
            ("uncertainty=True", "--uncertainty"),
            ("passive=False", "--driving-point no"), ("passive=True", "--driving-point yes"),
            ("passive='auto'", "--driving-point auto"),
            ("read_options={'conjugate': True}", "--conjugate"),
            ("read_options={'negate': True}", "--negate"),
            ("freq_hz=", "--freq-start/--df"),
            ("freq_range=(fmin, fmax)", "--fmin/--fmax"),
            ("make the FRF from them with modalid.frf_from_hammer",
             "make the FRF from them with modalid hammer FILES --out FRF.csv"),
            ("identify the body yourself (modalid.ModalFit) and give the saved fit "
             "(modalid.SavedFit.to_json, or modalid fit --out)",
             "identify the body yourself (modalid fit FILE --out DIR, with the options it "
             "needs) and give the _model.json it writes"),
            ("predict from its FRF file (or the fitted ModalFit)",
             "predict from its FRF file"),
            ("or use read_frfs", "or fit them all with common poles (modalid fit FILE --set "
             "--out DIR) and give the _set_model.json it writes"),
            ("pass driving_point= a row index or label, or None",
             "pass --driving-row (an output label, or a row index from 0)"),
            ("was passed: drop the argument", "was passed: drop the flag"),
            ("pass driving_point=", "pass --driving-row"),
            # a set read from the command line needs a driving row to be fitted
            ("or driving_point=None if there is none",
             "or, for a set measured at no excitation point, any row (the fit then finds "
             "it is not a driving point)"))

#: Python keyword -> flag: ``name=value`` becomes ``--flag value`` (quotes dropped); the
#: names with an underscore also bare (``window_decay_rate must be ...``)
_KEYWORDS = {
    # how the impact is predicted (impactpred predict, paper)
    "velocity1": "--v1", "velocity2": "--v2", "t_end": "--t-end", "dt": "--dt", "gap": "--gap",
    "contact": "--contact", "method": "--method",
    # how a file is read
    "quantity": "--quantity", "index": "--index", "format": "--format",
    # how an FRF is identified (ModalFit)
    "n_modes": "--n-modes", "freq_range": "--fmin/--fmax", "rigid_body": "--rigid-body",
    "weighting": "--weighting", "missed_modes": "--missed-modes",
    "window_decay_rate": "--window-decay", "record_length": "--record-length",
    # how a hammer test becomes an FRF (frf_from_hammer)
    "fs": "--fs", "response_type": "--response-type", "force_window": "--force-window",
    "force_window_length": "--force-window-length", "exponential_decay": "--exponential-decay",
    "n_fft": "--n-fft", "force_scale": "--force-scale", "response_scale": "--response-scale",
    "max_freq_hz": "--max-freq",
}


#: a name starts a word, not inside an identifier or a file path, nor a file's own text
#: quoted (``says '# record_length (s): abc'``)
_START = r"(?<![\w./\\'-])(?<!# )"


def in_flags(message) -> str:
    """``message`` on one line, with the Python argument names it mentions written as the
    command line's flags.

    ``t_end=8`` becomes ``--t-end 8``, ``missed_modes='dense'`` ``--missed-modes dense``,
    ``window_decay_rate must be ...`` ``--window-decay must be ...`` (and ``dt must ...``
    ``--dt must ...``), ``passive=False``
    ``--driving-point no``; see ``_PHRASES`` and ``_KEYWORDS``.
    """
    message = " ".join(str(message).split())
    for phrase, flag in _PHRASES:
        message = re.sub(_START + re.escape(phrase), flag, message)
    for name in sorted(_KEYWORDS, key=len, reverse=True):
        flag, word = _KEYWORDS[name], _START + re.escape(name)
        message = re.sub(word + r"=\s*(?:'([^']*)'|\"([^\"]*)\")",
                         lambda m, flag=flag: f"{flag} {m.group(1) or m.group(2) or ''}",
                         message)
        message = re.sub(word + r"=\s*", flag + " ", message)
        if "_" in name:
            message = re.sub(word + r"(?![\w=])", flag, message)
        else:        # "dt must be positive", not prose ("the quantity must be one of")
            message = re.sub(r"(?<!the )(?<!a )" + word + r"(?= must\b)", flag, message)
    return " ".join(message.split())


#: a negative number with an exponent, which argparse takes for an option
_NEGATIVE_EXPONENT = re.compile(r"^-(\d+\.?\d*|\.\d+)[eE][-+]?\d+$")


def _attached_negative_numbers(argv):
    """``argv`` with a negative number in exponent form after a long option attached to it
    (``--gap -1e-3`` -> ``--gap=-1e-3``): argparse reads ``-1e-3`` as an option and
    refused ``--gap -1e-3`` with "expected one argument" (``-0.001`` it reads)."""
    out = []
    for token in map(str, argv):
        if (out and _NEGATIVE_EXPONENT.match(token) and out[-1].startswith("--")
                and out[-1] != "--" and "=" not in out[-1]):
            out[-1] = f"{out[-1]}={token}"
        else:
            out.append(token)
    return out


def run_command(parser: argparse.ArgumentParser, argv=None, *,
                errors=(ValueError, TypeError, FileNotFoundError)) -> int:
    """Parse ``argv``, run the chosen sub-command's ``func``; bad input exits 2 with a message.

    Expected errors (bad values, missing files) are reported on one line, in flags
    (:func:`in_flags`), without a traceback; anything else propagates, since it is a bug.
    """
    args = parser.parse_args(_attached_negative_numbers(sys.argv[1:] if argv is None else argv))
    if not getattr(args, "func", None):
        parser.print_help()
        return 0
    try:
        return args.func(args)
    except errors as exc:
        print(f"{parser.prog}: error: {in_flags(exc)}", file=sys.stderr)
        return 2


def check_out_dir(out, *, flag: str = "--out") -> Path | None:
    """The output folder ``out`` as a Path (None without one), refused up front when it
    names an existing file (before any work, not after it).

    Raises
    ------
    ValueError
        ``out`` is empty, or exists and is not a folder.
    """
    if out is None:
        return None
    if not str(out).strip():          # Path("") is the current folder: not what was meant
        raise ValueError(f"{flag} is empty: give a folder (created if missing)")
    path = Path(out)
    if path.exists() and not path.is_dir():
        raise ValueError(f"{flag} {out} is an existing file, not a folder: give a folder "
                         "(created if missing)")
    return path


def nothing_saved(what: str) -> str:
    """The line a command prints when ``--out`` is not given."""
    return f"nothing saved (--out {what})"


# ------------------------------------------------------------------ identification options
def window_line(fit) -> str | None:
    """What a fit modelled of its data's windows and record end, and whence (the file's
    statement or a flag); None for a fit without either (or a saved fit).

    Parameters
    ----------
    fit : ModalFit or SavedFit
    """
    decay = getattr(fit, "window_decay_rate_", 0.0)
    length = getattr(fit, "record_length_", None)
    if not decay and length is None:
        return None

    def whence(name):
        return "as the file states" if getattr(fit, name) is None else "as given"

    parts = [f"exponential decay {decay:.6g} 1/s ({whence('window_decay_rate')})"] if decay \
        else []
    parts += [] if length is None else [f"record length {length:.6g} s "
                                        f"({whence('record_length')})"]
    return f"window modelled: {', '.join(parts)}; the model is the structure's"


def add_fit_options(parser: argparse.ArgumentParser, *, method_flags=("--method",)) -> None:
    """The :class:`modalid.ModalFit` options of every command that fits FRF files.

    Parameters
    ----------
    parser : argparse.ArgumentParser
    method_flags : tuple of str, keyword-only
        The flag(s) of the fit's method (``impactpred predict``, whose ``--method`` is the
        impact solver's, passes ``("--fit-method",)``).
    """
    parser.add_argument(*method_flags, dest="fit_method", choices=("lscf", "vf"), default=None,
                        help="identification method (default lscf)")
    parser.add_argument("--n-modes", type=int, default=None,
                        help="number of modes (default: chosen from the data)")
    parser.add_argument("--fmin", type=float, default=None, metavar="HZ",
                        help="lowest frequency (Hz); an end not given is chosen from the "
                             "data")
    parser.add_argument("--fmax", type=float, default=None, metavar="HZ",
                        help="highest frequency (Hz); an end not given is chosen from the "
                             "data")
    parser.add_argument("--rigid-body", choices=("auto", "yes", "no"), default=None,
                        help="a free body's mass line 1/(M s^2): auto (default) decides from "
                             "the data")
    parser.add_argument("--weighting", choices=("auto", "relative", "mixed", "noise", "uniform"),
                        default=None,
                        help="relative: noise proportional to the FRF; noise: a noise floor "
                             "estimated from the data (analyzer exports); auto (default): "
                             "decide from the data")
    parser.add_argument("--driving-point", choices=("auto", "yes", "no"), default=None,
                        help="yes: keep modal masses positive (a passive driving point); no: "
                             "allow negative ones (a transfer FRF); auto (default): decide "
                             "from the data")
    parser.add_argument("--not-driving-point", action="store_true",
                        help="the same as --driving-point no")
    parser.add_argument("--missed-modes", choices=("strict", "dense"), default=None,
                        help="dense: the fit adds every mode the residual and the "
                             "information criterion support (bands with many weak or close "
                             "modes); default strict")
    parser.add_argument("--window-decay", type=float, default=None, metavar="RATE",
                        help="the FRFs carry an exponential window exp(-RATE t) (1/s): the "
                             "fit models it and the models are without it")
    parser.add_argument("--record-length", type=float, default=None, metavar="T",
                        help="length (s) of the records behind the FRFs (no zero padding): "
                             "the fit undoes the record's end too")


_CHOICE = {"auto": "auto", "yes": True, "no": False}


def fit_options(args) -> dict:
    """The :class:`modalid.ModalFit` keyword arguments of :func:`add_fit_options`'s
    options, only those given.

    ``--fmin``/``--fmax`` give ``freq_range`` (None for the one left out: that end is
    chosen from the data);
    ``--driving-point``/``--not-driving-point`` give ``passive``.

    Raises
    ------
    ValueError
        ``--not-driving-point`` with ``--driving-point yes`` or ``auto``.
    """
    options = {}
    if args.fit_method is not None:
        options["method"] = args.fit_method
    if args.n_modes is not None:
        options["n_modes"] = args.n_modes
    if args.fmin is not None or args.fmax is not None:
        options["freq_range"] = (args.fmin, args.fmax)
    if args.rigid_body is not None:
        options["rigid_body"] = _CHOICE[args.rigid_body]
    if args.weighting is not None:
        options["weighting"] = args.weighting
    if args.not_driving_point and args.driving_point not in (None, "no"):
        raise ValueError(f"--not-driving-point contradicts --driving-point "
                         f"{args.driving_point}: give one of them")
    if args.not_driving_point:
        options["passive"] = False
    elif args.driving_point is not None:
        options["passive"] = _CHOICE[args.driving_point]
    if args.missed_modes is not None:
        options["missed_modes"] = args.missed_modes
    if args.window_decay is not None:
        options["window_decay_rate"] = args.window_decay
    if args.record_length is not None:
        options["record_length"] = args.record_length
    return options


# ------------------------------------------------------------------ reading options
def add_read_options(parser: argparse.ArgumentParser) -> None:
    """How an FRF file is read: ``--quantity``, ``--index``, ``--format``, for bare complex
    lines ``--freq-start``/``--df``, and ``--conjugate``/``--negate`` for a file stored with
    the other sign convention or the response's sign reversed."""
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
    parser.add_argument("--conjugate", action="store_true",
                        help="the file uses the other sign convention (Fourier kernel "
                             "exp(+i w t)): take the complex conjugate of its values")
    parser.add_argument("--negate", action="store_true",
                        help="the response was recorded in the opposite direction to the "
                             "force: reverse the sign of the values (a UFF record's own "
                             "directions are applied when it is read)")


def read_options(args, path) -> dict:
    """The :func:`modalid.read_frf` keyword arguments of :func:`add_read_options`'s options
    for the file ``path``, only those given.

    The line frequencies of a complex-lines file come from ``--freq-start`` (Hz, default 0)
    and ``--df`` (Hz): one per non-blank line of ``path``.

    Raises
    ------
    ValueError
        ``--df`` missing or not positive while ``--freq-start`` is given.
    FileNotFoundError
        ``--df`` given and ``path`` is not a file.
    """
    import numpy as np

    options = {"quantity": args.quantity, "index": args.index, "format": args.format,
               "conjugate": args.conjugate or None, "negate": args.negate or None}
    if args.df is not None or args.freq_start is not None:
        if args.df is None or not args.df > 0:
            given = "" if args.freq_start is None else f" with --freq-start {args.freq_start!r}"
            raise ValueError(f"--df must be a positive line spacing (Hz){given}, got "
                             f"{args.df!r}")
        if not Path(path).is_file():
            raise FileNotFoundError(f"no such file: {str(path)!r}")
        with open(path, encoding="utf-8-sig", errors="replace") as stream:
            n_lines = sum(1 for line in stream
                          if line.strip() and not line.lstrip().startswith("#"))
        start = 0.0 if args.freq_start is None else args.freq_start
        options["freq_hz"] = start + args.df * np.arange(n_lines)
        options["format"] = "complex-lines"
    return {k: v for k, v in options.items() if v is not None}


def uff_reading(path, options) -> str | None:
    """How the UFF record of ``path`` read with ``options`` (``read_frf``'s) was read: its
    DOFs, negated (directions of opposite sign), scaled to SI by its units dataset; None
    for another kind of file."""
    from .io_set import uff_record

    return record_reading(uff_record(path, options), options)


def record_reading(record, options) -> str | None:
    """:func:`uff_reading` of a record's metadata as
    :func:`modalid.io_set.uff_record` gives it (None: not a UFF file)."""
    from ._uff import dofs_text

    if record is None:
        return None
    said = ["UFF record {}: response {}, force {}".format(options.get("index") or 0,
                                                          *dofs_text(record))]
    if record["negated"]:
        said.append("read negated (its directions differ in sign)")
    if record["to_si"] != 1.0:
        said.append(f"values x {record['to_si']:.6g} to SI (its units dataset)")
    return ", ".join(said)
