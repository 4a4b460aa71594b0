"""Command line: ``impactpred <command>``; ``impactpred --help`` lists the commands."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from modalid._cli import (add_fit_options, add_read_options, check_out_dir, fit_options,
                          in_flags, nothing_saved, read_options, run_command, uff_reading,
                          window_line)

from ._cli_bodies import (BODY_FLAGS_HELP, add_body_flags, body_args, for_body, in_body_flags,
                          identification_flags, is_file_body)

__all__ = ["main"]

#: ``impactpred models`` prints at most this many frequencies per model
_MAX_LISTED_MODES = 1000
#: exit statuses beyond 0 (done) and 2 (a refused input): a prediction written but not
#: physical (its energy audit fails); a benchmark written that misses a target
EXIT_NOT_PHYSICAL, EXIT_TARGETS_MISSED = 3, 4


def _cmd_models(args) -> int:
    import numpy as np

    from data_synth import CantileverBeam, Rod, SpringMass

    out = check_out_dir(args.out)
    if not 1 <= args.n_modes <= _MAX_LISTED_MODES:
        raise ValueError(f"--n-modes must lie in [1, {_MAX_LISTED_MODES}] (frequencies printed "
                         f"per model), got {args.n_modes}")

    models = {
        "Rod(m=1 kg, T=1 s, fixed)": Rod(1.0, 1.0, support="fixed"),
        "Rod(m=1 kg, T=1 s, free)": Rod(1.0, 1.0, support="free"),
        "CantileverBeam(m=1 kg, T=1 s)": CantileverBeam(1.0, 1.0),
        "SpringMass(m=1 kg, k=1e4 N/m, zeta=0.02)": SpringMass(1.0, 1e4, damping_ratio=0.02),
    }
    print("First natural frequencies (Hz) of the exact models:")
    for name, model in models.items():
        n = 1 if isinstance(model, SpringMass) else args.n_modes
        freq_hz = model.natural_frequencies(n) / (2 * np.pi)
        print(f"  {name:42s} " + "  ".join(f"{f:9.4f}" for f in freq_hz))
    print(f"  {'LumpedMass(1 kg)':42s} (rigid body only)")
    if out is None:
        print(nothing_saved("DIR writes the FRF plot"))
    else:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        out.mkdir(parents=True, exist_ok=True)
        freq_hz = np.linspace(0.01, 4.0, 4000)
        fig, ax = plt.subplots(figsize=(7, 4))
        for name, model in models.items():
            if isinstance(model, SpringMass):
                continue
            ax.semilogy(freq_hz, np.abs(model.frf(2 * np.pi * freq_hz)), label=name, lw=1)
        ax.set_xlabel("frequency (Hz)")
        ax.set_ylabel("|receptance| (m/N)")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(out / "exact_models_frf.png", dpi=110)
        print(f"wrote {out / 'exact_models_frf.png'}")
    return 0


def _cmd_paper(args) -> int:
    import pandas as pd

    from .paper import run_paper_cases

    out = check_out_dir(args.out)
    table = run_paper_cases(out, dt=args.dt, plot=not args.no_plot)
    with pd.option_context("display.width", 160, "display.max_columns", 20):
        print(table.drop(columns=["description"]).to_string(float_format=lambda x: f"{x:.6g}"))
    print("Case (b): the paper's stepped force is the equal-mass reading (b_equal_mass); rods "
          "of the same material give a plain rectangular pulse 2 T2 wide (b_equal_material).")
    if out is None:
        print(nothing_saved("DIR writes the table as CSV and the Fig. 4 PNG files"))
    else:
        print(f"wrote {out / 'paper_cases.csv'}" + ("" if args.no_plot
                                                    else " and the Fig. 4 PNG files"))
    return 0


#: units of the columns of the CSV files ``impactpred predict`` writes
_UNITS = {"t": "t_s", "force": "force_N", "y1": "y1_m", "y2": "y2_m", "gap": "gap_m",
          "displacement": "displacement_m", "velocity": "velocity_m_s",
          "acceleration": "acceleration_m_s2"}


def _with_units(frame):
    """``frame`` with the project's units in its column and index names."""
    frame = frame.rename(columns=lambda c: _UNITS.get(c, c))
    frame.index = frame.index.rename(_UNITS.get(frame.index.name, frame.index.name))
    return frame


def _audit_line(res) -> str:
    audit = res.energy_audit
    verdict = "ok" if audit.ok else "FLAGGED: " + in_flags("; ".join(audit.reasons))
    return (f"{'energy_audit':>26s}: created {audit.created:.4g} J = {100 * audit.relative:.3g} "
            f"% of the {audit.scale:.4g} J the impact can redistribute (tolerance "
            f"{100 * audit.tolerance:.3g} %): {verdict}")


def _body_options(build, args, body: int, *extra):
    """``build(body_args(args, body), *extra)`` (``read_options``, ``fit_options``): body
    ``body``'s own flags (``--conjugate2``) over the common ones; an error names the flags
    as given for that body (``body 2: --freq-start2 ...``)."""
    try:
        return build(body_args(args, body), *extra)
    except (ValueError, TypeError) as exc:
        raise type(exc)(in_body_flags(str(exc), args, body)) from None


def _body_read_options(args, body: int) -> dict:
    """The ``read_frf`` options of body ``body`` (1 or 2) when it is an FRF file, else
    ``{}`` (see :func:`_body_options`)."""
    path = Path(getattr(args, f"body{body}"))
    if not path.is_file() or path.suffix.lower() == ".json":
        return {}
    return _body_options(read_options, args, body, path)


def _uff_reading(args, body: int) -> str | None:
    """How body ``body``'s UFF record was read (:func:`modalid._cli.uff_reading`), or
    None for another kind of body or file."""
    spec = getattr(args, f"body{body}")
    return uff_reading(spec, _body_read_options(args, body)) if is_file_body(spec) else None


def _check_identification_flags(args) -> str | None:
    """Refuse identification flags that no body uses; say which bodies ignore them.

    The flags apply to the bodies given as FRF files. With none, they would change
    nothing: a ``ValueError`` says why (a saved fit or model is identified already, a spec
    is exact). With one, a saved ``.json`` beside it keeps its own identification: the
    returned sentence says so (None when there is nothing to say). A body's own flags
    (``--conjugate2``) given for a body that is no file are refused.
    """
    from ._specs import is_spec

    def given(options):
        return [flag if value is True else f"{flag} {value}" for dest, flag in options.items()
                if (value := getattr(args, dest, None)) is not None and value is not False]

    specs = (args.body1, args.body2)
    saved = [not is_spec(s) and Path(s).suffix.lower() == ".json" for s in specs]
    files = [is_file_body(s) for s in specs]
    common = identification_flags(per_body=False)
    for i, (spec, is_file, is_saved) in enumerate(zip(specs, files, saved), start=1):
        own = given({f"{dest}_{i}": f"{flag}{i}" for dest, flag in common.items()})
        if own and not is_file:
            what = ("a saved fit or model, identified already: fit its FRF file again with "
                    "them and save it" if is_saved else "an exact model")
            raise ValueError(f"{' '.join(own)}: how body {i}'s FRF file is read and "
                             f"identified, and body {i} ({spec}) is {what}")
    common_given = given(common)
    if not common_given:
        return None
    flags = " ".join(common_given)
    if not any(files):
        what = "; ".join(
            f"body {i} ({s}) is a saved fit or model, identified already: fit its FRF file "
            f"again with them and save it (modalid fit FILE {flags} --out DIR)" if is_saved
            else f"body {i} ({s}) is an exact model"
            for i, (s, is_saved) in enumerate(zip(specs, saved), start=1))
        say = "these options say" if len(common_given) > 1 else "this option says"
        raise ValueError(f"{flags}: {say} how an FRF file is read and identified, and "
                         f"neither body is one: {what}")
    ignored = [f"body {i} ({s})" for i, (s, is_saved) in enumerate(zip(specs, saved), start=1)
               if is_saved]
    if ignored:
        used = " and ".join(f"body {i} ({s})" for i, (s, is_file)
                            in enumerate(zip(specs, files), start=1) if is_file)
        return (f"{flags} applied to {used} only: {ignored[0]} is a saved fit or model, "
                "identified with the options it was fitted with")
    return None


def _run_predict(args):
    """``(Prediction, warnings caught)`` of the ``predict`` command's arguments."""
    import warnings

    from modalid import ModalFit

    from .predict import predict

    # the same estimator as ``modalid fit`` builds (one line a segment of a wide band),
    # each body's own flags over the common ones
    options = [_body_options(fit_options, args, body) for body in (1, 2)]
    estimator = (ModalFit(progress=True, **options[0]) if options[0] == options[1]
                 else tuple(ModalFit(progress=True, **o) for o in options))
    ignored = _check_identification_flags(args)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        if ignored:
            warnings.warn(ignored, UserWarning, stacklevel=2)
        try:
            pred = predict(args.body1, args.body2, velocity1=args.v1, velocity2=args.v2,
                           gap=args.gap, contact=args.contact, t_end=args.t_end, dt=args.dt,
                           method=args.method, continuation=args.continuation,
                           uncertainty=args.uncertainty,
                           estimator=estimator,
                           read_options=tuple(_body_read_options(args, body)
                                              for body in (1, 2)),
                           check_passive=not args.no_passivity_check, progress=True,
                           band_check=not args.no_band_check)
        except RuntimeError as exc:
            if isinstance(exc, (NotImplementedError, RecursionError)):
                raise
            raise ValueError(f"the solver stopped: {exc}") from None
    return pred, caught


def _print_bodies(args, pred) -> None:
    import pandas as pd

    from modalid import SavedFit

    def figure(report, key, spec):
        """An entry formatted, the worst row's for a fit of several points; "n/a" where a
        saved fit's report lacks it."""
        value = report.get(key)
        if value is None:
            return "n/a"
        if isinstance(value, (list, tuple)):
            value = max(value)
        return format(value, spec)

    for i, fit in enumerate(pred.fits, start=1):
        if fit is None:
            continue
        report = fit.report_
        how = "saved fit" if isinstance(fit, SavedFit) else "identified from"
        print(f"body {i}: {how} {getattr(args, f'body{i}')} "
              f"({report['band_hz'][0]:.4g}-{report['band_hz'][1]:.4g} Hz, "
              f"FRF NRMSE {figure(report, 'frf_nrmse', '.3g')}, verdict "
              f"{report.get('verdict', 'ok')})")
        for line in (_uff_reading(args, i), window_line(fit)):
            if line is not None:
                print(f"  {line}")
        modes = report.get("modes")
        columns = ["frequency_hz", "damping_ratio", "modal_mass"]
        if modes is not None and set(columns) <= set(modes.columns):
            with pd.option_context("display.width", 140,
                                   "display.float_format", "{:.6g}".format):
                print(modes[columns].to_string())
        inverse_mass = report.get("inverse_mass")
        mass = (f" (mass {1 / inverse_mass:.6g} kg)" if report.get("rigid_body")
                and inverse_mass else "")
        print(f"  rigid body: {report.get('rigid_body', 'n/a')}{mass}, effective mass over "
              f"the band {figure(report, 'effective_mass', '.6g')} kg, residual flexibility "
              f"{figure(report, 'residual_flexibility', '.6g')} m/N; force energy above the "
              f"band: {100 * pred.band_reach[i - 1]:.2f} %, below it: "
              f"{100 * pred.band_reach_below[i - 1]:.2f} %")


def _continuation_line(pred) -> str:
    notes = [f"body {i}: {note}" for i, note in enumerate(pred.continuation, start=1)
             if note is not None]
    return f"{'continuation':>26s}: " + ("; ".join(notes) if notes else "no identified body")


def _print_summary(pred, summary) -> None:
    import pandas as pd

    res = pred.result
    for key, value in summary.items():
        print(f"{key:>26s}: {value}")
    intervals = [(round(a, 9), round(b, 9)) for a, b in res.contact_intervals]
    print(f"{'contact_intervals_s':>26s}: {intervals}")
    if res.dirac_impulses:
        shown = ", ".join(f"{p:.6g} N s at {t:.6g} s" for t, p in res.dirac_impulses[:3])
        more = f" and {len(res.dirac_impulses) - 3} more" if len(res.dirac_impulses) > 3 else ""
        print(f"{'dirac_impulses':>26s}: {shown}{more} (momentum passed at once: neither "
              "body gives at the contact, so the force there is unbounded; the peak forces "
              "above count the rest of the force only; a contact law with stiffness, "
              "--contact spring:stiffness=.. or hertz:stiffness=.., gives a finite peak)")
    print(_audit_line(res))
    with pd.option_context("display.width", 140, "display.float_format", "{:.6g}".format):
        print("energy (J):")
        print(res.energy.to_string())
        if any(p is not None for p in res.points):
            print("peaks at the output points (body, point):")
            print(res.point_peaks().to_string())
        if pred.uncertainty is not None:
            level = pred.uncertainty.level
            print("uncertainty band (" + (f"stated level {level:.0%} for the four figures "
                                          "together: " if level is not None else "")
                  + "parameter draws, widened by the truncation error of a re-identification "
                  "on 80 % of each band and the tail's; contact_duration and peak_force are "
                  "the first contact's, contacts closer than the bands resolve merged, "
                  "impulse and restitution over all contacts):")
            print(pred.uncertainty.table())


def _save_predict(pred, summary, out: Path) -> None:
    import matplotlib
    import pandas as pd

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    res = pred.result
    out.mkdir(parents=True, exist_ok=True)
    _with_units(res.to_pandas()).to_csv(out / "force_motion.csv")
    pd.DataFrame([summary]).to_csv(out / "summary.csv", index=False)
    res.energy.rename(columns=lambda c: f"{c}_J").rename_axis("body").to_csv(
        out / "energy.csv")
    for i, points in enumerate(res.points, start=1):
        if points is not None:
            _with_units(points.to_pandas()).to_csv(out / f"points_body{i}.csv")
    fig, ax = plt.subplots(figsize=(8, 4))
    res.plot(ax=ax)
    fig.tight_layout()
    fig.savefig(out / "impact.png", dpi=110)
    plt.close(fig)
    points = "".join(f", points_body{i}.csv" for i, p in enumerate(res.points, 1)
                     if p is not None)
    print(f"wrote force_motion.csv, summary.csv, energy.csv{points} and impact.png in {out}")


def _cmd_predict(args) -> int:
    out = check_out_dir(args.out)                 # before any work
    try:
        pred, caught = _run_predict(args)
    except ValueError as exc:                     # a body's remedy in that body's flags
        raise ValueError(for_body(in_flags(exc), args)) from None
    _print_bodies(args, pred)
    for w in caught:
        print(f"warning: {for_body(in_flags(w.message), args)}", file=sys.stderr)
    summary = pred.result.headline()
    if any(note is not None for note in pred.continuation):
        summary["continuation"] = _continuation_line(pred).split(": ", 1)[1]
    _print_summary(pred, summary)
    if out is None:
        print(nothing_saved("DIR writes force_motion.csv, summary.csv, energy.csv and "
                            "impact.png"))
    else:
        _save_predict(pred, summary, out)
    if not pred.result.energy_audit.ok:
        # written for inspection, but not an answer: the books do not balance
        print("error: the energy audit flags this prediction (see energy_audit above): "
              f"it is not physical; exit status {EXIT_NOT_PHYSICAL}", file=sys.stderr)
        return EXIT_NOT_PHYSICAL
    return 0


def _local_workers(scheduler):
    """Workers of ``--scheduler local[:N]`` (``os.cpu_count()`` for ``local``); None for an
    address."""
    name, _, count = scheduler.partition(":")
    if name != "local":
        return None
    if not count:
        return os.cpu_count() or 1
    if not count.isdigit() or int(count) < 1:
        raise ValueError(f"--scheduler local:N needs a worker count N >= 1, got {scheduler!r}")
    return int(count)


#: the benchmark's default grid (``run_benchmark``'s, noise in per cent); --quick runs its own
BENCHMARK_BANDS, BENCHMARK_NOISE = [10, 20, 40], [1.0, 5.0]


def _cmd_benchmark(args) -> int:
    import pandas as pd

    from .benchmark import error_table, markdown_table, run_benchmark

    check_out_dir(args.out)
    if args.quick and (args.bands != BENCHMARK_BANDS or args.noise != BENCHMARK_NOISE):
        raise ValueError("--quick runs 10 modes at 1 % noise on two cases: drop --bands and "
                         "--noise, or drop --quick")
    client = cluster = None
    if args.scheduler:                   # a Dask cluster's scheduler (dask is optional)
        n_local = _local_workers(args.scheduler)
        try:
            from dask.distributed import Client
        except ImportError as exc:
            raise ValueError("--scheduler needs Dask: pip install 'impactpred[distributed]'"
                             ) from exc
        if n_local is not None:          # a LocalCluster set up for these tasks
            from .parallel import local_cluster

            cluster = local_cluster(n_workers=n_local)
        client = Client(cluster if cluster is not None else args.scheduler)
    try:
        table = run_benchmark(quick=args.quick, out=args.out, progress=True,
                              bands=tuple(args.bands),
                              noises=tuple(n / 100 for n in args.noise),
                              workers=args.workers, executor=client)
    finally:
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()
    print(markdown_table(table))
    print(error_table(table))
    with pd.option_context("display.width", 140):
        print(table.attrs["targets"].to_string(index=False))
    print(f"total {table.attrs['seconds']:.0f} s; "
          + (f"wrote synthetic_benchmark.csv, .md and figures in {args.out}" if args.out
             else nothing_saved("DIR writes the CSV and markdown tables and the figures")))
    missed = int((table.attrs["targets"]["result"] == "MISS").sum())
    if missed:
        print(f"impactpred: {missed} of {len(table.attrs['targets'])} targets MISS; exit "
              f"status {EXIT_TARGETS_MISSED}", file=sys.stderr)
        return EXIT_TARGETS_MISSED
    return 0


def _add_predict_parser(sub) -> None:
    pred = sub.add_parser("predict", help="predict the impact of two bodies given as FRF "
                                          "files, saved fits or models (.json) or specs "
                                          "(mass:M, rod:..)")
    pred.add_argument("body1", help="body 1 (moving towards +y): FRF file, saved fit or model "
                                    ".json, or spec")
    pred.add_argument("body2", help="body 2")
    pred.add_argument("--v1", type=float, default=0.0,
                      help="rigid velocity of body 1 (m/s; default 0)")
    pred.add_argument("--v2", type=float, default=0.0,
                      help="rigid velocity of body 2 (m/s; default 0)")
    pred.add_argument("--gap", type=float, default=0.0, help="initial clearance (m; default 0)")
    pred.add_argument("--contact", default="rigid", help="rigid | spring:stiffness=.. | "
                      "hertz:stiffness=.. | hertz-sphere:radius1=..,youngs_modulus1=..,...")
    pred.add_argument("--t-end", type=float, required=True, help="end of the prediction (s)")
    pred.add_argument("--dt", type=float, default=None, help="time step (s); default: auto")
    pred.add_argument("--method", default="auto",
                      choices=("auto", "laplace", "modal", "convolution", "closed_form"),
                      help="the impact solver (the identification's: --fit-method)")
    continued = pred.add_mutually_exclusive_group()
    continued.add_argument("--continuation", dest="continuation", action="store_const",
                           const=True, default="auto",
                           help="continue every identified model above its band with the "
                                "high-frequency impedance of its top modes (default: those "
                                "with more than 0.1 %% of the force's energy above their "
                                "band)")
    continued.add_argument("--no-continuation", dest="continuation", action="store_const",
                           const=False, help="the identified models as they are")
    pred.add_argument("--uncertainty", action="store_true",
                      help="report the spread over cut-band re-identifications")
    pred.add_argument("--no-band-check", action="store_true",
                      help="skip the check that the answer does not move when each "
                           "identified body is re-identified on 80 %% of its band (one "
                           "re-identification and one solve per body; without "
                           "--uncertainty, which holds it)")
    pred.add_argument("--no-passivity-check", action="store_true",
                      help="accept models that are not stable, passive driving points "
                           "(negative modal masses, unstable poles, FRFs whose sign says "
                           "so): only for a model you can justify; the energy audit still "
                           "flags energy from nowhere. An FRF file its fit finds to be a "
                           "transfer FRF is refused all the same (--driving-point yes fits "
                           "it as a driving point)")
    read = pred.add_argument_group("reading the FRF files (as modalid fit)",
                                   description=BODY_FLAGS_HELP)
    add_read_options(read)
    fit = pred.add_argument_group("identifying the FRF files (as modalid fit)")
    add_fit_options(fit, method_flags=("--fit-method",))
    add_body_flags(pred)
    pred.add_argument("--out", metavar="DIR", help="folder for the CSV files (units in "
                      "their headers) and the plot (default: nothing saved)")
    pred.set_defaults(func=_cmd_predict)


def _mode_count(text) -> int:
    """``--bands``: a whole number of modes >= 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number of modes: {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"a band covers at least 1 mode, got {value}")
    return value


def _percent(text) -> float:
    """``--noise``: a finite level in per cent, >= 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not 0.0 <= value < 100.0:          # NaN fails too
        raise argparse.ArgumentTypeError(f"a noise level in per cent, at least 0 and under "
                                         f"100, got {text}")
    return value


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="impactpred",
        description="Predict impacts between linear structures from their driving-point "
                    "dynamics (Laplace-transform method).")
    sub = parser.add_subparsers(dest="command", metavar="command")
    models = sub.add_parser("models", help="print the exact models' natural frequencies, "
                                           "plot their FRFs")
    models.add_argument("--n-modes", type=int, default=5, help="frequencies per model")
    models.add_argument("--out", help="folder for the FRF plot")
    models.set_defaults(func=_cmd_models)
    paper = sub.add_parser("paper", help="reproduce the seed paper's Fig. 4 cases (a)-(d)")
    paper.add_argument("--out", help="folder for the PNG figures and the CSV table")
    paper.add_argument("--dt", type=float, default=None, help="time step (s); default: auto")
    paper.add_argument("--no-plot", action="store_true", help="table only")
    paper.set_defaults(func=_cmd_paper)
    _add_predict_parser(sub)
    bench = sub.add_parser("benchmark", help="synthetic hammer tests -> identification -> "
                                             "prediction, against the exact answers")
    bench.add_argument("--quick", action="store_true",
                       help="10 modes, 1 %% noise, two cases (seconds)")
    bench.add_argument("--bands", type=_mode_count, nargs="+", default=BENCHMARK_BANDS,
                       help="modes covered by the measured band")
    bench.add_argument("--workers", type=int, default=2,
                       help="processes (2 cases at one band each); the numbers do not "
                            "depend on it")
    bench.add_argument("--scheduler", metavar="ADDRESS", default=None,
                       help="run the tasks on a Dask cluster instead: its scheduler's "
                            "address (e.g. tcp://host:8786), or local[:N] to start a "
                            "LocalCluster of N workers (default: every core) set up for "
                            "these tasks (impactpred.parallel.local_cluster); needs "
                            "impactpred[distributed]")
    bench.add_argument("--noise", type=_percent, nargs="+", default=BENCHMARK_NOISE,
                       help="noise levels in per cent")
    bench.add_argument("--out", help="folder for the CSV and markdown tables and the figures")
    bench.set_defaults(func=_cmd_benchmark)
    return parser


def main(argv=None) -> int:
    """Entry point of the ``impactpred`` console script.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments without the program name; ``None`` reads ``sys.argv``.

    Returns
    -------
    int
        The exit status: 0 on success, 2 for a refused input, 3 for a prediction whose
        energy audit fails (written, but not physical), 4 for a benchmark that misses a
        target (written).
    """
    return run_command(build_parser(), argv)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
