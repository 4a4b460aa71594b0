"""Identification on real measured FRFs with no options, against published resonances.

Run:  python benchmarks/real_data.py [--quick]     (--quick leaves out the hammer test)

Each file is read as a user would and fitted with ``ModalFit()`` (no options: the band,
the weighting and whether it is a driving point are decided from the data). Against the
published (or observed) resonances it prints, per file: the band chosen, the weighting,
the driving-point decision, the verdict, the time, how many published resonances were
found within the tolerance the project targets, the worst frequency error, and the modes
fitted that match none of them. Beside it, sdypy-EMA's LSCF + LSFD (the ``bench``
extra), told the published frequencies (it cannot find them alone), on the same band.

Data (see each README for source and license):

* ``tests/data/case1.mat``, ``case2.mat``: vibration_toolbox analyzer exports (MIT),
  accelerance, 0-500 Hz; published 212.09 Hz (``sdof_cf``) and 192.59 Hz (``mdof_cf``).
* ``tests/data/meas_point_{1,2,3}.txt``: pyuff's measured accelerances (MIT), 0-1000 Hz
  at 1 Hz, observed peaks 52, 142, 279, 460, 687, 959 Hz (peak bins: a resonance lies
  within half a line of its bin).
* ``../shared/data/measured/pyfrf_hammer_impacts``: five hammer hits (GPL-3.0, read in
  place, never copied); H1 by ``frf_from_hammer`` with its defaults; 15 observed peaks.

It asserts nothing and always exits 0.
"""

from __future__ import annotations

import sys
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT / "tests" / "data"
SHARED = ROOT.parent / "shared" / "data" / "measured" / "pyfrf_hammer_impacts"

BEAM = [52, 142, 279, 460, 687, 959]
FILES = {
    "vtb case1": ("case1.mat", [212.09], 1e-3),
    "vtb case2": ("case2.mat", [192.59], 1e-3),
    "pyuff point 1": ("meas_point_1.txt", BEAM, 5e-3),
    "pyuff point 2": ("meas_point_2.txt", BEAM, 5e-3),
    "pyuff point 3": ("meas_point_3.txt", BEAM, 5e-3),
    "pyfrf hammer H1": (None, [810, 824, 851, 900, 1518, 2640, 3008, 3035, 3108, 3162, 3669,
                               4128, 4164, 4392, 4470], 3e-3),
}


def load(name):
    """The FRF of a benchmark file, as ``FRFData``."""
    from modalid import frf_from_hammer, read_frf

    file = FILES[name][0]
    if name.startswith("vtb"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")          # coherence clipped at a few lines
            return read_frf(DATA / file, quantity="accelerance")
    if name.startswith("pyuff"):
        n = sum(1 for _ in open(DATA / file))
        return read_frf(DATA / file, format="complex-lines", freq_hz=np.arange(float(n)),
                        quantity="accelerance")
    recs = [np.load(SHARED / f"measurements_{i}.npy", allow_pickle=False) for i in range(1, 6)]
    fs = 1.0 / (recs[0][0, 1] - recs[0][0, 0])
    return frf_from_hammer(np.array([r[1] for r in recs]), np.array([r[2] for r in recs]), fs,
                           response_type="acceleration").frf


def score(found_hz, published, tol):
    """``(n_found, worst relative error of those found, unmatched fitted modes)``."""
    found_hz = np.asarray(found_hz, float)
    errors = [np.min(np.abs(found_hz - p)) / p if found_hz.size else np.inf for p in published]
    hit = [e for e in errors if e < tol]
    unmatched = [round(float(f), 2) for f in found_hz
                 if np.min(np.abs(np.asarray(published) - f) / f) >= max(tol, 0.01)]
    return len(hit), (max(hit) if hit else np.nan), unmatched


def run_modalfit(frf, published, tol):
    from modalid import ModalFit

    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit().fit(frf)
    seconds = time.perf_counter() - t0
    r = fit.report_
    found, worst, unmatched = score(r["modes"]["frequency_hz"], published, tol)
    return fit, seconds, found, worst, unmatched


def run_sdypy(frf, band, published):
    """sdypy-EMA LSCF+LSFD told the published frequencies inside ``band``; None when the
    ``bench`` extra is missing."""
    try:
        sys.path.insert(0, str(Path(__file__).parent))
        from anchors import sdypy_lscf
    except ImportError:
        return None
    told = np.array([p for p in published if band[0] <= p <= band[1]], float)
    data = frf.band(band).to_receptance()
    try:
        poles, _, seconds = sdypy_lscf(data, told.size, approx_freq_hz=told)
    except ImportError:
        return None
    freq = np.abs(poles) / (2 * np.pi)
    zeta = -poles.real / np.abs(poles)
    return freq, zeta, seconds


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    names = [n for n in FILES if not ("--quick" in argv and n.startswith("pyfrf"))]
    if not SHARED.exists():
        names = [n for n in names if not n.startswith("pyfrf")]
    print("ModalFit() with no options on real measured FRFs; sdypy LSCF told the answers\n")
    for name in names:
        _, published, tol = FILES[name]
        frf = load(name)
        fit, seconds, found, worst, unmatched = run_modalfit(frf, published, tol)
        r = fit.report_
        band = r["band_hz"]
        print(f"{name}: {len(frf)} lines, {frf.quantity}")
        print(f"  band {band[0]:.6g}-{band[1]:.6g} Hz ({r['band_reason']})")
        print(f"  weighting {r['weighting']}; driving point {r['driving_point']} "
              f"({r['driving_point_reason']})")
        print(f"  verdict {r['verdict']}" + (f": {'; '.join(r['verdict_reasons'])}"
                                            if r["verdict_reasons"] else ""))
        print(f"  ModalFit: {found}/{len(published)} found within {100 * tol:.2g} % "
              f"(worst {100 * worst:.3g} %), {r['n_modes']} modes fitted, unmatched "
              f"{unmatched}, FRF error {100 * r['frf_nrmse']:.3g} %, "
              f"{seconds:.2f} s")
        modes = r["modes"]
        for p in published:
            k = int(np.argmin(np.abs(modes["frequency_hz"].to_numpy() - p))) if len(modes) \
                else None
            if k is None:
                continue
            row = modes.iloc[k]
            print(f"    {p:8.2f} Hz -> {row['frequency_hz']:9.3f} Hz, zeta "
                  f"{row['damping_ratio']:.3g} (resolved: {bool(row['damping_resolved'])})")
        ema = run_sdypy(frf, band, published)
        if ema is None:
            print("  sdypy-EMA: not installed (pip install -e .[bench])")
        else:
            f_e, z_e, s_e = ema
            e_found, e_worst, _ = score(f_e, published, tol)
            print(f"  sdypy LSCF (told {len(f_e)} frequencies): {e_found}/{len(published)} "
                  f"within {100 * tol:.2g} % (worst {100 * e_worst:.3g} %), {s_e:.2f} s; "
                  f"zeta {np.array2string(z_e, precision=3)}")
        print()
    return 0


if __name__ == "__main__":
    sys.exit(main())
