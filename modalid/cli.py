"""Command line: ``modalid fit FILE`` identifies a modal model from a measured FRF."""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

from ._cli import (add_fit_options, add_read_options, fit_options, in_flags, read_options,
                   run_command)

__all__ = ["main"]


def _passive(args):
    """``ModalFit(passive=...)`` from ``--driving-point`` (and its older spelling)."""
    if args.not_driving_point:
        return False
    return {"auto": "auto", "yes": True, "no": False}[args.driving_point]


def _cmd_fit(args) -> int:
    import pandas as pd

    from .fit import ModalFit
    from .io import read_frf

    data = read_frf(args.file, **read_options(args, args.file))
    freq_range = (args.fmin, args.fmax) if args.fmin is not None or args.fmax is not None \
        else None
    if freq_range is not None:
        freq_range = (args.fmin or 0.0, args.fmax or float(data.freq_hz[-1]))
    fit = ModalFit(method=args.method, freq_range=freq_range, n_modes=args.n_modes,
                   rigid_body={"auto": "auto", "yes": True, "no": False}[args.rigid_body],
                   passive=_passive(args), weighting=args.weighting,
                   **fit_options(args))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            fit.fit(data)
        except ValueError as exc:
            raise ValueError(f"{args.file}: {exc}") from None
    for w in caught:
        print(f"warning: {in_flags(str(w.message))}", file=sys.stderr)
    report = fit.report_
    print(f"{args.file}: {len(data)} lines, {data.freq_hz[0]:g}-{data.freq_hz[-1]:g} Hz, "
          f"{data.quantity}")
    columns = [c for c in ("frequency_hz", "damping_ratio", "modal_mass", "frequency_hz_std",
                           "damping_ratio_std", "damping_resolved")
               if c in report["modes"].columns]
    with pd.option_context("display.width", 140, "display.float_format", "{:.6g}".format):
        print(report["modes"][columns].to_string())
    print(f"rigid body: {report['rigid_body']} (inverse mass {report['inverse_mass']:.6g} 1/kg), "
          f"residual flexibility {report['residual_flexibility']:.6g} m/N, effective mass "
          f"{report['effective_mass']:.6g} kg")
    print(f"band {report['band_hz'][0]:g}-{report['band_hz'][1]:g} Hz: "
          f"{report['band_reason']}")
    if report.get("driving_point") is not None:
        print(f"driving point: {'yes' if report['driving_point'] else 'no'} "
              f"({report['driving_point_reason']})")
    print(f"FRF NRMSE {report['frf_nrmse']:.4g} ({data.quantity}); converged: "
          f"{report['converged']}")
    print(f"verdict: {report['verdict']}" + "".join(f"\n  - {r}"
                                                    for r in report["verdict_reasons"]))
    if not args.out:
        print("nothing saved (--out DIR writes the model JSON and the plots)")
    if args.out:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        stem = Path(args.file).stem
        fit.model_.to_json(out / f"{stem}_model.json")
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(2, 1, figsize=(8, 8))
        fit.plot_fit(ax=axes[0])
        fit.plot_stabilization(ax=axes[1])
        fig.tight_layout()
        fig.savefig(out / f"{stem}_fit.png", dpi=110)
        plt.close(fig)
        print(f"wrote {out / (stem + '_model.json')} and {out / (stem + '_fit.png')}")
    if report["verdict"] == "failed":
        print(f"{args.file}: the fit failed (see the verdict); try --fmin/--fmax, "
              "--weighting, --driving-point or --n-modes", file=sys.stderr)
        return 3
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="modalid", description="Identify pole-residue "
                                     "modal models from measured FRFs.")
    sub = parser.add_subparsers(dest="command", metavar="command")
    fit = sub.add_parser("fit", help="identify a modal model from an FRF file")
    fit.add_argument("file", help="CSV, .npz, .mat or UFF 58 file")
    add_read_options(fit)
    fit.add_argument("--method", choices=("lscf", "vf"), default="lscf")
    fit.add_argument("--n-modes", type=int, default=None, help="number of modes (default: auto)")
    fit.add_argument("--fmin", type=float, default=None,
                     help="lowest frequency (Hz); with neither --fmin nor --fmax the band is "
                          "chosen from the data")
    fit.add_argument("--fmax", type=float, default=None, help="highest frequency (Hz)")
    fit.add_argument("--rigid-body", choices=("auto", "yes", "no"), default="auto")
    fit.add_argument("--weighting", choices=("auto", "relative", "mixed", "noise", "uniform"),
                     default="auto",
                     help="relative: noise proportional to the FRF; noise: a noise floor "
                          "estimated from the data (analyzer exports); auto: decide from "
                          "the data")
    fit.add_argument("--driving-point", choices=("auto", "yes", "no"), default="auto",
                     help="yes: keep modal masses positive (a passive driving point); no: "
                          "allow negative ones (a transfer FRF); auto: decide from the data")
    fit.add_argument("--not-driving-point", action="store_true",
                     help="the same as --driving-point no")
    add_fit_options(fit)
    fit.add_argument("--out", help="folder for the model JSON and the plots")
    fit.set_defaults(func=_cmd_fit)
    return parser


def main(argv=None) -> int:
    """Entry point of the ``modalid`` console script."""
    return run_command(build_parser(), argv)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
