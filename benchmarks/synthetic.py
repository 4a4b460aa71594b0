"""Impact predictions from synthetic measured FRFs against the exact continuum answers.

Run:  python benchmarks/synthetic.py [--quick]

Cases (rigid contact, bodies at rest inside, approach speed 1 m/s):

* ``mass-rod M/m=1``, ``mass-rod M/m=2``: a rigid mass (known exactly) strikes the free
  end of a fixed rod (``m = 1 kg``, ``T = 1 s``) identified from its FRF. Exact answer:
  ``data_synth.reference_impacts.mass_on_fixed_rod`` (all contacts).
* ``rod-rod equal T``: two free rods (1 kg, ``T = 1 s``), +0.5 and -0.5 m/s, both
  identified. Exact: ``two_free_rods_equal_transit`` (e = 1, pulse 2T).
* ``rod-rod T2=0.75T1``: equal masses, ``T2 = 0.75 s``, both identified. Exact:
  ``solve_impact`` on the exact ``Rod`` models with the convolution solver, ``dt = T1/2000``
  (a divisor of both transit times).

Each identified body: truth ``lightly_damped(rod, n_in_band + 10, 0.005)``; receptance on
2000 lines from 0.02 Hz to midway between modes 10 and 11 (the band covers the first 10
modes), 1 % proportional noise, fixed seed; ``modalid.ModalFit()``; then
``continue_above_band`` (default, ``extend = 4``) and ``solve_impact`` (``laplace``).
Figures from ``impact_figures`` with contacts closer than ``1/(2 f_top)`` merged; the raw
count of contact intervals is printed too. The uncertainty band: re-identification on
60 % and 80 % of the band and 4 residue draws (``uncertainty_band``).

Columns: errors in per cent of the exact value (restitution and impulse after all
contacts, first-contact duration and peak force), whether the band contains the exact
value (y/n per figure: duration, peak, impulse, restitution), the damped truth model's own
restitution error (what the 0.5 % modal damping alone does, solved with the continuation
on the truth's modes) and the time per stage.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from data_synth import LumpedMass, Rod, lightly_damped, synthetic_frf  # noqa: E402
from data_synth.reference_impacts import (mass_on_fixed_rod,  # noqa: E402
                                          two_free_rods_equal_transit)
from impactpred import Body, solve_impact  # noqa: E402
from impactpred.truncation import (FIGURES, continue_above_band, identified_model,  # noqa: E402
                                   impact_figures, band_resolution, uncertainty_band)
from modalid import ModalFit  # noqa: E402

N_IN_BAND = 10
NOISE = 0.01
DAMPING = 0.005


def measure(rod, seed):
    truth = lightly_damped(rod, N_IN_BAND + 10, DAMPING)
    wn = truth.modes["omega_n"].to_numpy()
    top = 0.5 * (wn[N_IN_BAND - 1] + wn[N_IN_BAND]) / (2 * np.pi)
    freq = np.linspace(0.02, top, 2000)
    return truth, synthetic_frf(truth, freq, noise=NOISE, seed=seed)


def exact_mass_rod(ratio):
    t = np.linspace(0.0, 12.0, 240001)
    ref = mass_on_fixed_rod(ratio, 1.0, 1.0, 1.0, t)
    inside = t <= ref.separation_time
    return {"contact_duration": ref.separation_time, "peak_force": float(ref.force[inside].max()),
            "impulse": ref.total_impulse, "restitution": ref.restitution}


def exact_rod_rod_equal():
    ref = two_free_rods_equal_transit(1.0, 1.0, 1.0, 0.5, -0.5, np.linspace(0, 4, 9))
    return {"contact_duration": ref.contact_duration, "peak_force": ref.force_height,
            "impulse": ref.impulse, "restitution": ref.restitution}


def exact_rod_rod_075(t_end):
    res = solve_impact(Body(Rod(1.0, 1.0), velocity=0.5), Body(Rod(1.0, 0.75), velocity=-0.5),
                       t_end=t_end, dt=1.0 / 2000, method="convolution")
    return impact_figures(res)


CASES = {
    "mass-rod M/m=1": dict(bodies=("mass", Rod(1.0, 1.0, support="fixed")), v=(1.0, 0.0),
                           M=1.0, t_end=12.0, exact=lambda: exact_mass_rod(1.0)),
    "mass-rod M/m=2": dict(bodies=("mass", Rod(1.0, 1.0, support="fixed")), v=(1.0, 0.0),
                           M=2.0, t_end=16.0, exact=lambda: exact_mass_rod(2.0)),
    "rod-rod equal T": dict(bodies=(Rod(1.0, 1.0), Rod(1.0, 1.0)), v=(0.5, -0.5),
                            t_end=6.0, exact=exact_rod_rod_equal),
    "rod-rod T2=0.75T1": dict(bodies=(Rod(1.0, 1.0), Rod(1.0, 0.75)), v=(0.5, -0.5),
                              t_end=6.0, exact=lambda: exact_rod_rod_075(6.0)),
}


def run_case(name, case, *, uncertainty=True, n_draws=4):
    timing = {}
    t0 = time.perf_counter()
    exact = case["exact"]()
    timing["exact"] = time.perf_counter() - t0
    models, fits, truths = [], [], []
    t0 = time.perf_counter()
    for i, body in enumerate(case["bodies"]):
        if body == "mass":
            models.append(LumpedMass(case["M"]))
            fits.append(None)
            truths.append(LumpedMass(case["M"]))
            continue
        truth, data = measure(body, seed=10 + i)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fit = ModalFit().fit(data)
        fits.append(fit)
        truths.append(truth)
    timing["identify"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    for fit in fits:
        if fit is not None:
            models.append(identified_model(fit))
    models = [m for m in models]
    timing["continue"] = time.perf_counter() - t0
    v1, v2 = case["v"]

    def solve(m1, m2):
        return solve_impact(Body(m1, velocity=v1), Body(m2, velocity=v2), t_end=case["t_end"],
                            method="laplace")

    t0 = time.perf_counter()
    nominal = solve(*models)
    timing["predict"] = time.perf_counter() - t0
    resolution = band_resolution(fits)
    figs = impact_figures(nominal, resolution=resolution)
    # without the continuation (the pseudo-modes and flexibility of the fit only)
    plain = [f.model_ if f is not None else m for f, m in zip(fits, models)]
    figs_plain = impact_figures(solve(*plain), resolution=resolution)
    # what the truth's own damping does: the truth's modes, continued, solved exactly
    truth_models = []
    for f, tr in zip(fits, truths):
        if f is None:
            truth_models.append(tr)
        else:
            truth_models.append(continue_above_band(tr.truncate(N_IN_BAND, residual=True),
                                                    f.report_["band_hz"][1]))
    figs_truth = impact_figures(solve(*truth_models), resolution=resolution)
    band = None
    if uncertainty:
        t0 = time.perf_counter()
        band = uncertainty_band(models, fits, solve, n_draws=n_draws, nominal=nominal)
        timing["band"] = time.perf_counter() - t0
    return dict(name=name, exact=exact, figs=figs, plain=figs_plain, truth=figs_truth,
                band=band, timing=timing)


def pct(value, ref):
    return 100.0 * (value - ref) / ref


def table(rows):
    head = ("| case | duration % | peak % | impulse % | e % | e predicted (exact) | "
            "contacts merged/raw | e % no continuation | e % damped truth | "
            "band contains D/P/J/e | band e | time ident/cont/predict/band s |")
    out = [head, "|" + "---|" * (head.count("|") - 1)]
    for r in rows:
        ex, f = r["exact"], r["figs"]
        errs = [pct(f[k], ex[k]) for k in FIGURES]
        band = r["band"]
        contains = ("/".join("y" if band.contains(k, ex[k]) else "n" for k in FIGURES)
                    if band else "-")
        band_e = f"{band.low['restitution']:.4f}-{band.high['restitution']:.4f}" if band else "-"
        tm = r["timing"]
        out.append(
            f"| {r['name']} | {errs[0]:+.2f} | {errs[1]:+.2f} | {errs[2]:+.2f} | "
            f"{errs[3]:+.2f} | {f['restitution']:.4f} ({ex['restitution']:.4f}) | "
            f"{f['n_contacts']}/{f['n_contacts_raw']} | "
            f"{pct(r['plain']['restitution'], ex['restitution']):+.2f} | "
            f"{pct(r['truth']['restitution'], ex['restitution']):+.2f} | {contains} | "
            f"{band_e} | {tm['identify']:.2f}/{tm['continue']:.3f}/{tm['predict']:.2f}/"
            f"{tm.get('band', float('nan')):.1f} |")
    return "\n".join(out)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="no uncertainty band")
    args = parser.parse_args(argv)
    rows = []
    for name, case in CASES.items():
        rows.append(run_case(name, case, uncertainty=not args.quick))
    print(table(rows))
    print()
    for r in rows:
        if r["band"] is not None:
            print(f"{r['name']}: exact " + ", ".join(f"{k}={r['exact'][k]:.5g}" for k in FIGURES))
            print(r["band"].table())
            print()


if __name__ == "__main__":
    main()
