"""Command line: ``modalid fit FILE`` identifies a modal model from a measured FRF (``modalid
fit FILE FILE...`` or ``--set``: one common-pole model of several FRFs, with mode shapes);
``modalid hammer FILE...`` turns raw impact-hammer records into an FRF file."""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

from ._cli import (add_fit_options, add_read_options, check_out_dir, fit_options, in_flags,
                   nothing_saved, read_options, record_reading, run_command, window_line)
from ._cli_set import print_shapes, read_set

__all__ = ["main", "build_parser"]


def _warn(message) -> None:
    print(f"warning: {in_flags(message)}", file=sys.stderr)


# ------------------------------------------------------------------------------ fit
def _print_report(args, data, report, window=None) -> None:
    import numpy as np
    import pandas as pd

    rows = (f"{len(data.outputs)} FRFs ({', '.join(map(str, data.outputs))}), "
            if hasattr(data, "outputs") else "")
    print(f"{args.file}: {rows}{len(data)} lines, {data.freq_hz[0]:g}-{data.freq_hz[-1]:g} Hz, "
          f"{data.quantity}")
    columns = [c for c in ("frequency_hz", "damping_ratio", "modal_mass", "frequency_hz_std",
                           "damping_ratio_std", "damping_resolved")
               if c in report["modes"].columns]
    with pd.option_context("display.width", 140, "display.float_format", "{:.6g}".format):
        print(report["modes"][columns].to_string())
    print(f"rigid body: {report['rigid_body']} (inverse mass {report['inverse_mass']:.6g} 1/kg), "
          f"residual flexibility {report['residual_flexibility']:.6g} m/N, effective mass over "
          "the band "
          f"{report['effective_mass']:.6g} kg")
    print(f"band {report['band_hz'][0]:g}-{report['band_hz'][1]:g} Hz: "
          f"{in_flags(report['band_reason'])}")
    if window is not None:
        print(window)
    # a set's decision is its driving row's (its "driving_point" is the row's index)
    decision = report.get("driving_row_is_driving_point", report.get("driving_point"))
    if decision is not None:
        print(f"driving point: {'yes' if decision else 'no'} "
              f"({in_flags(report['driving_point_reason'])})")
    nrmse = report.get("frf_nrmse_data", report["frf_nrmse"])     # the data's quantity
    nrmse = (f"{nrmse:.4g}" if np.ndim(nrmse) == 0 else          # a set: one per row
             ", ".join(f"{label} {e:.4g}" for label, e in zip(data.outputs, nrmse)))
    print(f"FRF NRMSE {nrmse} ({data.quantity}); converged: {report['converged']}")
    print(f"verdict: {report['verdict']}" + "".join(f"\n  - {in_flags(r)}"
                                                    for r in report["verdict_reasons"]))


def _save_fit(fit, out: Path, stem: str, source: str, *, several: bool = False,
              body: bool = True, record=None) -> None:
    import matplotlib

    from ._uff import DOF_KEYS, dofs_text
    from .saved_fit import SavedFit

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out.mkdir(parents=True, exist_ok=True)
    # the model with the fit's band, verdict and decisions: a prediction uses it as it
    # uses the FRF file's fit (the bare model would be used raw, without its band)
    # (with the UFF record's DOFs: a transfer record by them is refused as a body)
    dofs = None if record is None else tuple(int(record[k]) for k in DOF_KEYS)
    saved = SavedFit.from_fit(fit, source=source, record_dofs=dofs)
    saved.to_json(out / f"{stem}_model.json")
    coherence = getattr(fit.data_, "coherence", None) is not None
    rows = 3 if coherence else 2                  # magnitude, phase (, coherence)
    # constrained layout: the chart's legend above it takes its own room, not a gap
    # between every panel (as tight_layout spread it)
    fig, axes = plt.subplots(rows + 1, 1, figsize=(8, 3.0 + 2.2 * rows), layout="constrained",
                             gridspec_kw={"height_ratios": [3.0, 1.5, 1.0][:rows] + [3.0]})
    fit.plot_fit(ax=axes[:rows])
    fit.plot_stabilization(ax=axes[rows])
    fig.savefig(out / f"{stem}_fit.png", dpi=110)
    plt.close(fig)
    if not several and saved.dofs_say_transfer:
        use = (f"the fit of a transfer FRF by its record's DOFs (response {dofs_text(record)[0]}, "
               f"force {dofs_text(record)[1]}): impactpred predict refuses it as a body, as it "
               f"refuses {source}")
    elif not several:
        use = f"the fit: impactpred predict takes it in place of {source}, with the same results"
    elif body:
        use = "the common-pole fit: impactpred predict takes it as a body, its driving row's model"
    else:
        row = fit.model_.outputs[fit.model_.driving_point]
        use = (f"the common-pole fit of transfer FRFs: modes and shapes, not an impact body "
               f"(its driving row {row} is not a driving point)")
    print(f"wrote {out / (stem + '_model.json')} ({use}) and {out / (stem + '_fit.png')}")


def _cmd_fit(args) -> int:
    from ._sign import check_sign
    from .fit import ModalFit
    from .io import read_frf
    from ._uff import dofs_text, says_transfer
    from .io_set import uff_record

    out = check_out_dir(args.out)                 # before any work
    fit = ModalFit(progress=True, **fit_options(args))    # a wide band: one line a segment
    several = args.set or len(args.file) > 1
    if args.driving_row is not None and not several:
        raise ValueError("--driving-row names a row of a set: give several files or --set")
    paths = args.file
    with warnings.catch_warnings(record=True) as caught:     # said as the fit's are
        warnings.simplefilter("always")
        if several:
            data = read_set(args)
        else:
            data = read_frf(paths[0], **read_options(args, paths[0]))
    for w in caught:
        _warn(w.message)
    record = None                                 # a single UFF file's record metadata
    if several:
        args.file = " + ".join(Path(f).name for f in paths)
        # the sign check reads the driving row (named: the message is about one FRF)
        judged, named = data.driving, f"{args.file} (row {data.outputs[data.driving_point]})"
    else:
        judged = data
        args.file = named = paths[0]
        record = uff_record(paths[0], read_options(args, paths[0]))   # read once
        reading = record_reading(record, read_options(args, paths[0]))
        if reading is not None:
            print(f"{paths[0]}: {reading}")
    sign = check_sign(judged)
    applied = [k for k in ("conjugate", "negate") if getattr(args, k)]
    if sign.verdict != "ok":
        _warn(sign.problem(named, applied=applied))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            fit.fit(data)
        except ValueError as exc:
            raise ValueError(f"{args.file}: {exc}") from None
    for w in caught:
        _warn(w.message)
    report = fit.report_
    _print_report(args, data, report, window_line(fit))
    # the record's DOFs go with the fit, unless it was fitted as a driving point as
    # asserted (--driving-point yes: DOFs written wrong)
    if fit.passive is True:
        record = None
    if record is not None and says_transfer(record) and report.get("driving_point"):
        _warn("the record's DOFs (response {}, force {}) say a transfer FRF, though its "
              "data look like a driving point's: impactpred predict refuses it as a body "
              "(if the DOFs are written wrong, fit it with --driving-point yes)"
              .format(*dofs_text(record)))
    if several:
        print_shapes(fit)
    stem = Path(paths[0]).stem + ("_set" if several else "")
    if out is None:
        print(nothing_saved("DIR writes the model JSON and the plots"))
    else:
        body = not several or bool(report["driving_row_is_driving_point"])
        _save_fit(fit, out, stem, Path(args.file).name if not several else args.file,
                  several=several, body=body, record=record)
    if report["verdict"] == "failed":
        fix = (f"; {in_flags(sign.problem(named, applied=applied))}"
               if sign.verdict != "ok" else "")
        print(f"{args.file}: the fit failed (see the verdict); try --fmin/--fmax, "
              f"--weighting, --driving-point or --n-modes{fix}", file=sys.stderr)
        return 3
    return 0


# --------------------------------------------------------------------------- hammer
def _check_frf_out(out):
    """``--out FILE`` of ``modalid hammer``: a writable format, not a folder, not an
    existing file (a measured FRF is not overwritten)."""
    if out is None:
        return None
    from .io import WRITE_FORMATS, _format_of

    path = Path(out)
    if path.is_dir():
        raise ValueError(f"--out {out} is a folder: give the FRF file to write (.csv, .npz, "
                         ".mat or .uff)")
    if path.exists():        # a measured FRF is not overwritten without a word
        raise ValueError(f"--out {out} exists: remove it first, or give another name")
    try:
        _format_of(path, None, WRITE_FORMATS)
    except ValueError:             # its hint names format=, which hammer has no flag for
        raise ValueError(f"--out {out}: its extension says the format; give .csv, .npz, "
                         ".mat or .uff") from None
    return path


def _excited_top(est) -> float:
    """The highest line (Hz) where the force spectrum is within 20 dB of its maximum."""
    import numpy as np

    spectrum = est.force_spectrum
    return float(est.frf.freq_hz[np.flatnonzero(spectrum >= 0.01 * spectrum.max())[-1]])


def _fit_flags(est) -> str:
    """The ``modalid fit`` / ``impactpred predict`` flags of the estimate's windows."""
    options = est.fit_options()
    flags = ([f"--window-decay {options['window_decay_rate']:.9g}"]
             if options["window_decay_rate"] else [])
    if options["record_length"] is not None:
        flags.append(f"--record-length {options['record_length']:.9g}")
    return " ".join(flags)


def _cmd_hammer(args) -> int:
    import numpy as np

    from ._hammer_files import read_hammer_records
    from .hammer import frf_from_hammer
    from .io import _EXTENSIONS, write_frf

    out = _check_frf_out(args.out)                # before any work
    records = read_hammer_records(args.files, fs=args.fs, time=args.time, force=args.force,
                                  response=args.response, force_scale=args.force_scale,
                                  response_scale=args.response_scale)
    response_type = args.response_type or records.response_type or "acceleration"
    if records.response_type not in (None, response_type):
        raise ValueError(f"--response-type {response_type}, but the response channel's unit "
                         f"or name says {records.response_type}: drop the flag, or name the "
                         "channel you mean with --response")
    n_hits, n_samples = records.force.shape
    uff = out is not None and _EXTENSIONS.get(out.suffix.lower()) == "uff"
    pretrigger = "keep" if uff and args.pretrigger == "auto" else args.pretrigger
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        est = frf_from_hammer(records.force, records.response, records.fs,
                              response_type=response_type, force_window=args.force_window,
                              force_window_length=args.force_window_length,
                              exponential_decay=args.exponential_decay, n_fft=args.n_fft,
                              baseline=args.baseline, pretrigger=pretrigger,
                              max_freq_hz=args.max_freq)
    for w in caught:
        _warn(w.message)
    frf = est.frf
    files = list(dict.fromkeys(records.sources))
    named = files[0] if len(files) == 1 else f"{files[0]} ... {files[-1]}"
    print(f"{n_hits} hit{'s' * (n_hits > 1)} from {len(files)} file"
          f"{'s' * (len(files) > 1)} ({named}): {n_samples} samples at {records.fs:.9g} Hz "
          f"({n_samples / records.fs:.6g} s); channels: {records.channels}")
    starts = est.force_window_starts
    window = ("none" if est.force_window_length is None
              else f"force window to {est.force_window_length:.6g} s" if starts is None
              else f"force window to {est.force_window_length:.6g} s after the cut"
              if est.record_starts is not None
              else f"force window from {_span(starts)} s (the hits' starts, less five "
                   f"widths) to {est.force_window_length:.6g} s")
    if est.record_starts is not None:           # cut: never zero-padded, so a length
        print(f"pre-trigger cut: each hit's records from {_span(est.record_starts)} s (its "
              f"force window's start), {est.record_length:.6g} s kept (--pretrigger keep: "
              "whole)")
    elif pretrigger != args.pretrigger and not est.window_decay_rate and args.n_fft is None \
            and any(est.force_window_starts or ()):
        print("pre-trigger kept (--pretrigger auto with a .uff file: it holds a round line "
              "spacing only; a .csv, .npz or .mat file keeps the cut records' lines)")
    decay = est.window_decay_rate
    duration = est.record_length if est.record_length is not None else n_samples / records.fs
    ends = f", ending at {np.exp(-decay * duration):.3g}" if decay else ""
    print(f"windows: {window}; exponential decay {decay:.6g} 1/s{ends}")
    units = ("N", {"acceleration": "m/s^2", "velocity": "m/s"}.get(response_type, "m"))
    removed = [f"{name} {value:.6g} {unit}" for name, value, unit
               in zip(("force", "response"), est.offsets or (0.0, 0.0), units) if value]
    if removed:
        print(f"offsets removed (each channel's pre-trigger mean, where significant): "
              f"{', '.join(removed)}")
    coherence = ("" if frf.coherence is None
                 else f", median coherence {np.median(frf.coherence[1:]):.4f}")
    print(f"H1 {frf.quantity}: {len(frf)} lines, {frf.freq_hz[0]:g}-{frf.freq_hz[-1]:g} Hz"
          f"{coherence}; the force spectrum is within 20 dB of its maximum up to "
          f"{_excited_top(est):.6g} Hz")
    if est.double_hits:
        print(f"double hits in hits {list(est.double_hits)} (averaged all the same)")
    target = out if out is not None else "FILE"
    if out is None or not uff:
        # a CSV/NPZ/MAT file keeps the force spectrum, and the fit's band ends with it
        kept = ("the force spectrum the file keeps" if out is not None
                else "the force spectrum (kept by a .csv, .npz or .mat file)")
        reach = (f"(its automatic band ends where {kept} falls 20 dB, "
                 f"near {_excited_top(est):.6g} Hz)" if frf.coherence is None else
                 f"(its automatic band keeps the lines above where {kept} falls 20 dB, near "
                 f"{_excited_top(est):.6g} Hz, while their coherence stays at 0.9 or more)")
    else:
        reach = f"(and --fmax {_excited_top(est):.6g} to keep to the band the hammer excited)"
    stated = [what for what, there in (("the exponential window", decay),
                                       ("the record length", est.record_length is not None))
              if there]
    told = (f"; the file keeps {' and '.join(stated)} ({_fit_flags(est)}), which the fit "
            "then models" if stated else "")
    print(f"fit it with: modalid fit {target} {reach}{told}; impactpred predict takes the "
          "file as it is")
    if not decay:
        end = ("which the fit takes out (the file keeps the record length)"
               if est.record_length is not None else
               "which no fit can take out of a zero-padded FFT's lines")
        print(f"no exponential window: where a mode has not died out within the record, "
              f"its end puts terms on the FRF's lowest lines, {end}; --exponential-decay "
              f"{4.6 * records.fs / n_samples:.3g} (a window ending at 1 % of the whole records, "
              "which it keeps) makes them small")
    if out is None:
        print(nothing_saved("FILE writes the FRF with its coherence (.csv, .npz, .mat, .uff)"))
    else:
        out.parent.mkdir(parents=True, exist_ok=True)
        try:
            write_frf(out, frf)
        except ValueError as exc:           # an ASCII UFF's 6-digit line spacing
            if "ASCII UFF" not in str(exc):
                raise
            cut = (" (the records cut at the hits): give --pretrigger keep, or"
                   if est.record_starts is not None else ":")
            raise ValueError(f"{out}: an ASCII UFF file holds lines on a spacing of 6 "
                             f"significant digits, and these are {frf.freq_hz[1]:.10g} Hz "
                             f"apart{cut} write a .csv, .npz or .mat file") from None
        print(f"wrote {out}")
    return 0


# --------------------------------------------------------------------------- parser
def _add_fit_parser(sub) -> None:
    fit = sub.add_parser("fit", help="identify a modal model from an FRF file (or, with "
                                     "common poles, from several FRFs)")
    fit.add_argument("file", nargs="+", metavar="FILE",
                     help="CSV, .npz, .mat, UFF 58 or complex-lines file; several files: "
                          "one common-pole fit of all their FRFs (as --set)")
    fit.add_argument("--set", action="store_true",
                     help="fit every FRF of the files together, with common poles (one "
                          "file holding several FRFs, e.g. a UFF of several points): the "
                          "modes, their shapes and a model of every row")
    fit.add_argument("--driving-row", metavar="ROW", default=None,
                     help="the set's row measured at the excitation point (index from 0, "
                          "or output label); default: from the UFF records' DOFs")
    add_read_options(fit)
    add_fit_options(fit)
    fit.add_argument("--out", metavar="DIR", help="folder for the model JSON and the plots "
                                                  "(default: nothing saved)")
    fit.set_defaults(func=_cmd_fit)


def _channel(text):
    return int(text) if text.isdigit() else text


def _add_hammer_parser(sub) -> None:
    hammer = sub.add_parser("hammer", help="raw impact-hammer records -> an FRF file (H1 "
                                           "with coherence)")
    hammer.add_argument("files", nargs="+", metavar="FILE",
                        help=".npy (channels as rows or columns), .npz (named arrays), "
                             "CSV or LabVIEW .lvm (.lvm.gz) records; several files (or .lvm "
                             "segments) are several hits, averaged")
    hammer.add_argument("--fs", type=float, default=None, metavar="HZ",
                        help="sample rate (Hz) when the files have no time channel (one "
                             "rounded in its text is checked against it)")
    hammer.add_argument("--time", type=_channel, default=None, metavar="NAME|INDEX",
                        help="the time channel (s); default: by name (t, time), else the "
                             "first of three channels")
    hammer.add_argument("--force", type=_channel, default=None, metavar="NAME|INDEX",
                        help="the force channel (N); default: by name (force, f), else the "
                             "second of three channels (first of two)")
    hammer.add_argument("--response", type=_channel, default=None, metavar="NAME|INDEX",
                        help="the response channel; default: by name (response, "
                             "acceleration, velocity, displacement), else the last")
    hammer.add_argument("--response-type", default=None,
                        choices=("acceleration", "velocity", "displacement"),
                        help="the response's kind (m/s^2, m/s or m): the FRF is "
                             "accelerance, mobility or receptance; default: as the "
                             "channel's unit or name says, else acceleration")
    for role, unit in (("force", "N"), ("response", "m/s^2, m/s or m")):
        hammer.add_argument(f"--{role}-scale", type=float, default=None, metavar="SI_PER_UNIT",
                            help=f"multiply the {role} channel by this ({unit} per unit of "
                                 "the file: a sensor's sensitivity for volts); its stated "
                                 "unit is then not read")
    hammer.add_argument("--exponential-decay", type=float, default=0.0, metavar="RATE",
                        help="exponential window exp(-RATE t) on both channels (1/s; for a "
                             "window ending at e: -ln(e)/T); default none")
    hammer.add_argument("--force-window", choices=("force", "none"), default="force",
                        help="force: zero the force record before and after the pulse "
                             "(default)")
    hammer.add_argument("--force-window-length", type=float, default=None, metavar="S",
                        help="length (s) of the force window from the record start; default: "
                             "from five pulse widths before each hit to five widths after "
                             "its last pulse (a double hit's second one included)")
    hammer.add_argument("--baseline", choices=("pretrigger", "none"), default="pretrigger",
                        help="pretrigger: remove a channel's offset, its mean before the hits "
                             "where significant (default); none: the records as they are")
    hammer.add_argument("--pretrigger", choices=("auto", "cut", "keep"), default="auto",
                        help="cut: each hit's records from its force window's start, the "
                             "samples before it dropped, so that the record's end is modelled "
                             "for a hit at its start (with the automatic force window and no "
                             "--n-fft); keep: the records whole, on the lines of their full "
                             "length; auto (default): cut without --exponential-decay (and "
                             "not for a .uff file: it holds a round line spacing only)")
    hammer.add_argument("--n-fft", type=int, default=None, metavar="N",
                        help="FFT length, zero-padded (default: the record length)")
    hammer.add_argument("--max-freq", type=float, default=None, metavar="HZ",
                        help="the highest line written (default and most: fs / 2; an "
                             "analyzer's lines stop at fs / 2.56, where its anti-aliasing "
                             "filter rolls off)")
    hammer.add_argument("--out", metavar="FILE",
                        help="the FRF file to write (.csv, .npz, .mat, .uff; default: "
                             "nothing saved)")
    hammer.set_defaults(func=_cmd_hammer)


def build_parser() -> argparse.ArgumentParser:
    """The ``modalid`` command line's parser.

    Returns
    -------
    argparse.ArgumentParser
        With its ``fit`` and ``hammer`` commands.
    """
    parser = argparse.ArgumentParser(prog="modalid", description="Identify pole-residue "
                                     "modal models from measured FRFs.")
    sub = parser.add_subparsers(dest="command", metavar="command")
    _add_fit_parser(sub)
    _add_hammer_parser(sub)
    return parser


def _span(values) -> str:
    """``a-b`` of the smallest and largest of ``values``, or ``a`` when they are one."""
    low, high = min(values), max(values)
    return f"{low:.6g}" if low == high else f"{low:.6g}-{high:.6g}"


def main(argv=None) -> int:
    """Entry point of the ``modalid`` console script.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments without the program name; ``None`` reads ``sys.argv``.

    Returns
    -------
    int
        The exit status: 0 on success, 2 for a refused input, 3 for a failed fit.
    """
    return run_command(build_parser(), argv)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
