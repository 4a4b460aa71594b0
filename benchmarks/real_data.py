"""Identification on real measured FRFs with no options, against published resonances.

Run:  python benchmarks/real_data.py [--quick]     (--quick leaves out the hammer test)

Each file is read as a user would and fitted with ``ModalFit()`` (no options: the band,
the weighting and whether it is a driving point are decided from the data). Against the
published (or observed) resonances it prints, per file: the band chosen, the weighting,
the driving-point decision, the verdict, the time, how many published resonances were
found within the tolerance the project targets (or half a line, where that is wider: a
published peak bin places a resonance no closer), the worst frequency error, and the modes
fitted that match none of them. Beside it, sdypy-EMA's LSCF + LSFD (the ``bench``
extra), told the published frequencies (it cannot find them alone), on the same band;
and per published resonance the damping ratios of ModalFit, sdypy and the half-power
method (:func:`half_power_damping`), with whether ModalFit's lies within the spread of
the other two or is flagged as not resolved.

Data (see each README for source and license):

* ``tests/data/case1.mat``, ``case2.mat``: vibration_toolbox analyzer exports (MIT),
  accelerance, 0-500 Hz; published 212.09 Hz (``sdof_cf``) and 192.59 Hz (``mdof_cf``).
* ``tests/data/meas_point_{1,2,3}.txt``: pyuff's measured accelerances (MIT), 0-1000 Hz
  at 1 Hz, observed peaks 52, 142, 279, 460, 687, 959 Hz (peak bins: a resonance lies
  within half a line of its bin).
* ``../shared/data/measured/pyfrf_hammer_impacts``: five hammer hits (GPL-3.0, read in
  place, never copied); H1 by ``frf_from_hammer`` with its defaults; 15 observed peaks.
* ``tests/data/acceleration.lvm.gz``: one hammer hit on a free beam with an accelerometer
  (ladisk's image-based modal analysis tutorial, MIT; LabVIEW text, 50 kHz, 1 s) read as
  ``modalid hammer`` reads it, FRF by ``frf_from_hammer`` with its defaults; published
  695.0, 1897.6, 2777.3 and 3671.2 Hz with damping ratios 0.0047, 0.0031, 0.0024 and
  0.0020 (the tutorial's pyEMA LSCF on 1-4000 Hz).

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
    "ladisk beam, one hit": ("acceleration.lvm.gz", [695.0, 1897.6, 2777.3, 3671.2], 3e-3),
}
#: damping ratios the publisher gives, per published resonance
PUBLISHED_DAMPING = {"ladisk beam, one hit": [0.0047, 0.0031, 0.0024, 0.0020]}
#: the top of the band the publisher fitted (Hz), where it is below the file's: modes
#: above it match nothing published and are not counted as matching none
PUBLISHED_TOP = {"ladisk beam, one hit": 4000.0}


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
    if name.startswith("ladisk"):                 # as `modalid hammer FILE` reads it
        from modalid._hammer_files import read_hammer_records

        hit = read_hammer_records([DATA / file])
        return frf_from_hammer(hit.force, hit.response, hit.fs,
                               response_type="acceleration").frf
    recs = [np.load(SHARED / f"measurements_{i}.npy", allow_pickle=False) for i in range(1, 6)]
    fs = 1.0 / (recs[0][0, 1] - recs[0][0, 0])
    return frf_from_hammer(np.array([r[1] for r in recs]), np.array([r[2] for r in recs]), fs,
                           response_type="acceleration").frf


def score(found_hz, published, tol, half_line):
    """``(n_found, worst relative error of those found, unmatched fitted modes)``: a
    published resonance is found within ``tol`` (relative) of it or half a line
    (``half_line``, Hz) where that is wider, as on the user bands (a peak bin, pyuff's
    52 Hz, places a resonance only to half a line: its lines at 51 and 52 Hz stand at 7.8
    and 8.4, a sharp resonance at 51.52 Hz)."""
    found_hz = np.asarray(found_hz, float)
    errors = [np.min(np.abs(found_hz - p)) if found_hz.size else np.inf for p in published]
    hit = [e / p for e, p in zip(errors, published) if e <= max(tol * p, half_line)]
    unmatched = [round(float(f), 2) for f in found_hz
                 if np.min(np.abs(np.asarray(published) - f) / f) >= max(tol, 0.01)]
    return len(hit), (max(hit) if hit else np.nan), unmatched


def run_modalfit(frf, published, tol):
    half_line = 0.5 * float(np.median(np.diff(frf.freq_hz)))
    from modalid import ModalFit

    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit().fit(frf)
    seconds = time.perf_counter() - t0
    r = fit.report_
    found, worst, unmatched = score(r["modes"]["frequency_hz"], published, tol, half_line)
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


def half_power_damping(frf, f0_hz, *, search=0.003):
    """Damping ratio of the resonance near ``f0_hz`` by the half-power method on ``|H|``
    in the data's own quantity: the peak line within ``search`` (relative; three lines at
    least) of ``f0_hz``, the width where ``|H|`` falls to ``peak / sqrt(2)``
    (``scipy.signal.peak_widths``, interpolated between lines), ``zeta = width / (2
    f_peak)``. Returns ``(zeta, resolved)``: resolved when the width spans two lines or
    more (a narrower peak's width is the line spacing's, not the mode's). A close
    neighbour's skirt widens it: the method is a single-mode one."""
    from scipy.signal import peak_widths

    f, mag = frf.freq_hz, np.abs(frf.values)
    spacing = float(np.median(np.diff(f)))
    near = np.flatnonzero(np.abs(f - f0_hz) <= max(search * f0_hz, 3.0 * spacing))
    if near.size == 0:
        return np.nan, False
    k = int(near[np.argmax(mag[near])])
    # the height relative to a "prominence" of the peak's own height: peak / sqrt(2)
    width, *_ = peak_widths(mag, [k], rel_height=1.0 - 1.0 / np.sqrt(2.0),
                            prominence_data=(mag[[k]], np.array([0]),
                                             np.array([mag.size - 1])))
    return float(width[0] * spacing / (2.0 * f[k])), bool(width[0] >= 2.0)


#: ModalFit's damping agrees with the others' when within their spread widened by this
#: factor either way (the scatter between estimators on the same measured data)
SPREAD_MARGIN = 1.25


def damping_rows(fit, frf, published, ema, tol):
    """Per published resonance ModalFit found (within ``tol``): its damping ratio (and
    whether it says it resolved it), sdypy's for the same resonance, the half-power
    estimate; and whether ModalFit's lies within the spread of the other two (widened by
    :data:`SPREAD_MARGIN`; the half-power figure where it resolved the peak) or is
    flagged unresolved: True, False, or None when neither gave a figure."""
    modes = fit.report_["modes"]
    rows = []
    for p in published:
        if not len(modes):
            continue
        k = int(np.argmin(np.abs(modes["frequency_hz"].to_numpy() - p)))
        row = modes.iloc[k]
        if abs(row["frequency_hz"] / p - 1) >= tol:
            continue
        z_fit, resolved = float(row["damping_ratio"]), bool(row["damping_resolved"])
        z_ema = np.nan
        if ema is not None and len(ema[0]):
            j = int(np.argmin(np.abs(ema[0] - p)))
            z_ema = float(ema[1][j]) if abs(ema[0][j] / p - 1) < 0.01 else np.nan
        z_hp, hp_resolved = half_power_damping(frf, p)
        others = [z for z in (z_ema, z_hp if hp_resolved else np.nan) if np.isfinite(z)]
        within = (True if not resolved else None if not others
                  else min(others) / SPREAD_MARGIN <= z_fit <= max(others) * SPREAD_MARGIN)
        rows.append((p, float(row["frequency_hz"]), z_fit, resolved, z_ema, z_hp, hp_resolved,
                     within))
    return rows


def subband_check(frf, fit):
    """The reported standard deviations against refits on sub-bands: ``ModalFit`` on the
    lower and the upper 70 % of the band the whole fit chose; for every mode of the
    whole fit in the middle 90 % of a sub-band and found there (within 1 %), the change
    of its frequency and damping ratio over the two fits' stds combined. The fits share
    lines, so calibrated stds give ratios below 1 on average; far above 1 they are
    optimistic. Returns ``(pairs, rms df/std, rms dzeta/std over modes whose damping both
    fits resolve)``."""
    from modalid import ModalFit

    lo, hi = fit.report_["band_hz"]
    whole = fit.report_["modes"]
    df, dz = [], []
    for a, b in ((lo, lo + 0.7 * (hi - lo)), (lo + 0.3 * (hi - lo), hi)):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sub = ModalFit(freq_range=(a, b)).fit(frf).report_["modes"]
        for _, m in whole.iterrows():
            f = m["frequency_hz"]
            if not a + 0.05 * (b - a) < f < b - 0.05 * (b - a):
                continue
            s = sub.iloc[int(np.argmin(np.abs(sub["frequency_hz"].to_numpy() - f)))]
            if abs(s["frequency_hz"] - f) > 0.01 * f:
                continue
            df.append((s["frequency_hz"] - f) / np.hypot(m["frequency_hz_std"],
                                                         s["frequency_hz_std"]))
            if m["damping_resolved"] and s["damping_resolved"]:
                dz.append((s["damping_ratio"] - m["damping_ratio"])
                          / np.hypot(m["damping_ratio_std"], s["damping_ratio_std"]))
    def rms(v):
        return float(np.sqrt(np.nanmean(np.square(v)))) if len(v) else float("nan")

    return len(df), rms(df), rms(dz)


#: bands a user may choose on each file (Hz), for :func:`user_bands`
USER_BANDS = {
    "vtb case1": [(150, 300), (100, 400), (20, 250), (190, 240)],
    "vtb case2": [(150, 260), (180, 205), (20, 400), (100, 300)],
    "pyuff": [(9, 702.3), (300, 1000), (20, 1000), (2, 1000), (100, 800), (40, 600),
              (150, 900), (9, 500), (30, 300), (200, 1000), (5, 990), (60, 999), (120, 520)],
    "pyfrf hammer H1": [(500, 5000), (700, 1000), (2500, 3800), (4000, 4600), (100, 6000),
                        (780, 950), (1400, 1600), (2900, 3200), (10, 4600), (3500, 4500)],
    "ladisk beam, one hit": [(1, 4000), (10, 4000), (500, 3000), (100, 6000), (1500, 4000),
                             (600, 800), (2500, 3900)],
}


def user_bands(names):
    """``ModalFit(freq_range=band)`` on bands a user may choose (:data:`USER_BANDS`),
    nothing else set: per file (pyuff: each point and the three as a set with common
    poles) the published resonances inside the bands found (within the file's tolerance
    or half a line), the modes matching none of them (not counted for the hammer test,
    whose list is of its 15 clearest peaks only, nor above the band a publisher fitted,
    :data:`PUBLISHED_TOP`), and the verdicts. Rows of
    ``(label, found, expected, unmatched, ok, failed, seconds)``."""
    from modalid import FRFSet, ModalFit

    rows = []
    jobs = []
    for name in names:
        jobs.append((name, load(name)))
        if name == "pyuff point 3":
            sets = [load(f"pyuff point {k}") for k in (1, 2, 3)]
            jobs.append(("pyuff set (common poles)",
                         FRFSet(sets[0].freq_hz, np.array([d.values for d in sets]),
                                quantity="accelerance", driving_point=0)))
    for label, data in jobs:
        key = "pyuff" if label.startswith("pyuff") else label
        published = np.array(FILES["pyuff point 1" if key == "pyuff" else label][1], float)
        tol = FILES["pyuff point 1" if key == "pyuff" else label][2]
        found = expected = unmatched = ok = failed = 0
        t0 = time.perf_counter()
        for band in USER_BANDS[key]:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                fit = ModalFit(freq_range=band).fit(data)
            r = fit.report_
            lo, hi = r["band_hz"]
            half_line = 0.5 * float(np.median(np.diff(data.freq_hz)))
            reach = np.maximum(tol * published, half_line)
            inside = (published > lo) & (published < hi)
            f = r["modes"]["frequency_hz"].to_numpy()
            near = np.abs(f[:, None] - published[None, :]) <= reach[None, :]
            found += int(np.sum(near.any(axis=0) & inside))
            expected += int(inside.sum())
            if not label.startswith("pyfrf"):
                f = f[f <= PUBLISHED_TOP.get(label, np.inf)]
                unmatched += int(np.sum(~(np.abs(f[:, None] - published[None, :])
                                          <= np.maximum(0.01 * published, half_line)).any(1)))
            ok += r["verdict"] == "ok"
            failed += r["verdict"] == "failed"
        rows.append((label, found, expected, unmatched, ok, failed,
                     time.perf_counter() - t0))
    return rows


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
        print(f"  ModalFit: {found}/{len(published)} found within {100 * tol:.2g} % or half "
              f"a line (worst {100 * worst:.3g} %), {r['n_modes']} modes fitted, unmatched "
              f"{unmatched}, FRF error {100 * r['frf_nrmse']:.3g} %, "
              f"{seconds:.2f} s")
        ema = run_sdypy(frf, band, published)
        rows = damping_rows(fit, frf, published, ema, tol)
        print("    published ->  ModalFit: frequency, zeta (resolved) | sdypy zeta | "
              "half-power zeta (resolved) | ModalFit's zeta within their spread or flagged")
        for p, f_fit, z_fit, res, z_ema, z_hp, hp_res, within in rows:
            print(f"    {p:8.2f} Hz -> {f_fit:9.3f} Hz, {z_fit:9.3g} ({'yes' if res else 'no '})"
                  f" | {z_ema:9.3g} | {z_hp:9.3g} ({'yes' if hp_res else 'no '}) | "
                  f"{'-' if within is None else 'yes' if within else 'NO'}")
        pairs, rms_f, rms_z = subband_check(frf, fit)
        print(f"  sub-band refits (lower and upper 70 % of the band): {pairs} modes, rms "
              f"change over the stds: frequency {rms_f:.2f}, damping {rms_z:.2f} (resolved)")
        if name in PUBLISHED_DAMPING:
            fitted = {p: z for p, _, z, *_ in rows}
            print("    published damping -> ModalFit: " + ", ".join(
                f"{z:.4g} -> {fitted.get(p, np.nan):.4g}"
                for p, z in zip(published, PUBLISHED_DAMPING[name])))
        judged = [r[-1] for r in rows if r[-1] is not None]
        print(f"  damping: {sum(judged)}/{len(judged)} within the spread of sdypy and the "
              f"half-power estimate (x/÷ {SPREAD_MARGIN}), or flagged unresolved")
        if ema is None:
            print("  sdypy-EMA: not installed (pip install -e .[bench])")
        else:
            f_e, z_e, s_e = ema
            e_found, e_worst, _ = score(f_e, published, tol,
                                        0.5 * float(np.median(np.diff(frf.freq_hz))))
            print(f"  sdypy LSCF (told {len(f_e)} frequencies): {e_found}/{len(published)} "
                  f"within {100 * tol:.2g} % or half a line (worst {100 * e_worst:.3g} %), "
                  f"{s_e:.2f} s")
        print()
    print("ModalFit(freq_range=band) on bands a user may choose (USER_BANDS), no other option")
    for label, found, expected, unmatched, ok, failed, seconds in user_bands(names):
        spurious = "-" if label.startswith("pyfrf") else str(unmatched)
        n = len(USER_BANDS["pyuff" if label.startswith("pyuff") else label])
        print(f"  {label:26s} {n:2d} bands: {found}/{expected} published resonances found, "
              f"{spurious} modes matching none, verdict ok {ok} / failed {failed}, "
              f"{seconds:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
