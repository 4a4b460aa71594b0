"""Bands of many modes, fitted with no options: every mode found, none invented.

Run:  python benchmarks/many_modes.py [--quick]

Three structures, 40-50 modes each on 1 Hz .. 20 kHz: a fixed rod (modes every 500 Hz
from 250 Hz, equal modal masses), a free rod (a rigid-body mass line and modes every
500 Hz from 500 Hz) and a random set (50 modes placed uniformly at random between 200 Hz
and 19.8 kHz, at least two half-power bandwidths (4 zeta) and 0.5 % apart, modal masses
0.5-5 kg, each damping ratio within a factor 2 of the nominal), all of one nominal
damping ratio (1e-4, 1e-3, 1e-2: at the top
of a rod's band, modal overlap ``2 zeta f / 500 Hz`` of 0.008, 0.08 and 0.8), on 2401,
4001 or 8001 lines, noise-free and with 1 % noise proportional to the FRF
(:func:`data_synth.synthetic_frf`, seed 1). Each FRF is fitted by ``ModalFit()`` with no
options. A mode counts as found when a fitted mode lies within 0.1 % of its frequency
(or half a line); a fitted mode near none is *extra*.

Per setting it prints modes found / modes in the band, extra modes, the largest
relative frequency error of the modes found, the FRF error, the verdict, the number of
segments and the fit's time, then the totals. ``--quick``: the 4001-line rows only.
It asserts nothing and always exits 0; ``tests/test_modalid_segments.py`` asserts the
fixed rod's rows at 1e-3
(4001 lines) and 1e-2 (8001 lines).
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np

from data_synth import lightly_damped, random_modal_model, synthetic_frf
from data_synth.rod import Rod
from modalid import ModalFit

F_TOP = 20000.0
ZETAS = (1e-4, 1e-3, 1e-2)
NOISES = (0.0, 0.01)
LINES = (2401, 4001, 8001)
TOLERANCE = 1e-3


def structure(name, zeta):
    """The truth (a ModalModel) of the structure ``name`` at damping ``zeta``."""
    if name == "random":
        return random_modal_model(50, (200.0, F_TOP - 200.0), zeta, seed=7)
    return lightly_damped(Rod(1.0, 1e-3, support=name.split()[0]), 80, zeta)


def true_frequencies(model):
    """The truth's elastic natural frequencies (Hz) inside the band."""
    p = np.asarray(model.poles)
    f = np.abs(p[p.imag > 0]) / (2 * np.pi)
    return np.sort(f[f < F_TOP])


def score(truth_hz, fitted_hz, spacing_hz):
    """``(found, extra, worst relative error of the found)``."""
    tol = np.maximum(TOLERANCE * truth_hz, spacing_hz / 2)
    if fitted_hz.size == 0:
        return 0, 0, np.nan
    gap = np.abs(truth_hz[:, None] - fitted_hz[None, :])
    found = gap.min(axis=1) <= tol
    extra = int(np.sum(gap.min(axis=0) > tol[gap.argmin(axis=0)]))
    worst = float(np.max(gap.min(axis=1)[found] / truth_hz[found])) if found.any() else np.nan
    return int(found.sum()), extra, worst


def run(lines=LINES):
    print(f"{'structure':10} {'zeta':>6} {'noise':>5} {'lines':>5} | {'found':>7} {'extra':>5} "
          f"{'worst err':>9} {'FRF err':>8} {'verdict':8} {'segs':>4} {'time':>6}")
    totals = np.zeros(3)
    started = time.perf_counter()
    for name in ("fixed rod", "free rod", "random"):
        for zeta in ZETAS:
            truth = structure(name, zeta)
            exact = true_frequencies(truth)
            for n_lines in lines:
                freq = np.linspace(1.0, F_TOP, n_lines)
                for noise in NOISES:
                    data = synthetic_frf(truth, freq, noise=noise, seed=1)
                    began = time.perf_counter()
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore")
                        fit = ModalFit().fit(data)
                    took = time.perf_counter() - began
                    report = fit.report_
                    fitted = report["modes"]["frequency_hz"].to_numpy(float)
                    found, extra, worst = score(exact, fitted, freq[1] - freq[0])
                    totals += (found, exact.size, extra)
                    print(f"{name:10} {zeta:6.0e} {noise:5.2f} {n_lines:5d} | "
                          f"{found:3d}/{exact.size:<3d} {extra:5d} {worst:9.1e} "
                          f"{report['frf_nrmse']:8.2%} {report['verdict']:8} "
                          f"{report['segments']:4d} {took:5.1f}s", flush=True)
    print(f"total: {int(totals[0])}/{int(totals[1])} modes found, {int(totals[2])} extra, "
          f"{time.perf_counter() - started:.0f} s")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the 4001-line rows only")
    args = parser.parse_args(argv)
    run((4001,) if args.quick else LINES)


if __name__ == "__main__":
    main()
