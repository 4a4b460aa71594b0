"""Accuracy and speed of ``modalid.fit.ModalFit`` against exact truths.

Run:  python benchmarks/bench_identification.py [--seeds 5] [--quick] [--anchors]
      python benchmarks/bench_identification.py --bound-sweep   (the beam's Cramer-Rao bound
      over damping and line count only)

The cases (fixed inputs)
------------------------
Driving-point receptances of four structures, each given the light damping
``zeta = 0.01`` on every mode: the truth is ``model.modal_model(8 + 10, damping_ratio=0.01,
residual=True)``, i.e. the 8 modes of the band, 10 more above it and the exact static
flexibility of the rest:

* ``beam``: ``CantileverBeam(1, 1)`` (tip; modes span 160:1, the first under-resolved);
* ``fixed rod``: ``Rod(1, 1, support="fixed")``;
* ``free rod``: ``Rod(1, 1, support="free")`` (rigid-body mode, mass 1 kg);
* ``short rod``: ``Rod(0.3, 0.01, support="fixed")`` (the fixed rod in other units:
  a 0.3 kg rod with a 10 ms transit time, band up to 400 Hz).

4000 lines linearly spaced on ``(0, f_max]``, ``f_max`` halfway between modes 8 and 9.
Noise proportional to the FRF: ``H (1 + eta (n1 + i n2) / sqrt(2))``, ``n ~ N(0, 1)``,
``eta`` in {0, 1 %, 5 %}, seeds 0-4 (``numpy.random.default_rng(seed)``).
ERA rows: the truth's impulse response, 8000 samples at 2.5 times the frequency of its
highest (18th) mode, no noise.

Fits use the defaults, ``ModalFit()`` (automatic order, mode count, low-end terms and
residuals), and ``method="vf"`` / ``"era"`` where stated.

Metrics, per dataset and noise level, worst over the seeds and the 8 modes of the band
------------------------------------------------------------------------------------
``df``, ``dz``, ``dr``: relative errors of natural frequency, damping ratio and complex
residue of the worst mode; ``dM``: relative error of the rigid-body mass (free rod);
``nrmse``: ``|H_fit - H| / |H|`` over the band against the noisy data, and (``vs true``)
against the noise-free truth: worst seed, dominated by the highest peaks; ``rel``: the
rms over the lines of ``|H_fit / H_true - 1|`` (every line counts alike); ``bad``:
missed, spurious, unstable or negative-mass modes over all seeds; ``t``: median CPU time
per FRF (s), BLAS pinned to one thread (``time.process_time``; on a shared machine wall
times vary by 2x). The ``floor`` rows fit the right model (the 8 modes, modes 9-10 as two
upper pseudo-modes, the constant and the rigid term) started from the true values with
the same weighted refinement: what the noise allows. Below the table, per mode at 5 %
noise: the worst errors and the standard deviations the fit reports.

Information bound
-----------------
After the table (full runs), ``information_bound`` prints, at 5 % noise, what *any*
unbiased fit of the floor's model can reach on these data: the Cramer-Rao bound of
``identification_bound.py`` (Fisher information of the proportional complex noise,
linearised), as the median over runs of the worst-of-``--seeds`` errors and the
probability ``P`` that one run of ``--seeds`` seeds meets each target. Below it, the
per-seed medians of ``df`` and ``vs true`` over 20 seeds for the bound, the floor fit and
``ModalFit()``: when the three agree, the linearisation holds and ModalFit is efficient.

Anchors (``--anchors``)
-----------------------
With ``--anchors`` the same run also fits every dataset with the third-party anchors of
``anchors.py`` (optional ``bench`` extra: scikit-rf, sdypy-EMA; python-control), called
exactly as there (its functions are imported, not copied) and, as there, *told* the model:

* ``skrf VF0`` / ``skrf VF2``: scikit-rf vector fitting with 8 complex starting poles
  (the 8 in-band modes) and 0 or 2 real ones, constant term fitted;
* ``sdypy LSCF`` / ``sdypy LSCE``: sdypy-EMA poles (orders up to 30) picked at the 8 true
  natural frequencies, LSFD residues with lower and upper residuals;
* ``ctrl ERA 2r`` / ``ctrl ERA 500``: python-control ERA of the truth's order (18 modes,
  +2 for the rigid body), Hankel size python-control's default ``2 r`` or 500, residues by
  least squares.

They run on *this* script's data, not on ``identification_data.make_case`` (whose truth,
``data_synth.lightly_damped``, and noise draw, ``data_synth.synthetic_frf``, differ from
``frf_case`` here): the FRF anchors get the very ``frf_case(name, noise, seed)`` arrays
ModalFit gets (noise 0, 1 %, 5 %; same seeds, or the first ``--anchor-seeds``), the ERA
anchors the very ``impulse_case(name)`` record of the ``era clean`` row. Every anchor's
poles and residues become a ``ModalModel`` scored by the same :func:`mode_errors` as the
ModalFit rows (same matching, same ``bad`` count), timed the same way (CPU time of the
call). The anchors return modes only (no residual terms, no rigid-body mass), so their
``dM``, ``nrmse``, ``vs true`` and ``rel`` are ``n/a`` (``-`` in ``dM`` means the dataset
has no rigid body), and ``conv`` is ``-``. An anchor that raises counts its 8 modes as
``bad`` and is reported below the table. Noise-free FRF rows of the anchors use seed 0
only (the data do not depend on the seed; ModalFit's noise-free rows repeat the same data
over the seeds). The closing lines compare, per dataset at 5 % noise, ModalFit's
(``lscf``) worst-mode ``df``, ``dz``, ``dr`` with the best FRF anchor's for each metric,
among the FRF anchors with ``bad = 0`` at 5 % (all of them, marked ``*``, when none has;
the ERA anchors run on clean impulse records only and are not in it). The anchors add
about 40 s to a 5-seed run on a 2-core machine (whole run about 1 minute).
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402

from data_synth import CantileverBeam, Rod  # noqa: E402
from modalid import FRFData, ModalModel  # noqa: E402
from modalid._lsfd import Terms, refine_varpro, split_coefficients  # noqa: E402
from modalid.fit import ModalFit  # noqa: E402

N_BAND, N_ABOVE, ZETA, N_LINES = 8, 10, 0.01, 4000
DATASETS = {
    "beam": lambda: CantileverBeam(1.0, 1.0),
    "fixed rod": lambda: Rod(1.0, 1.0, support="fixed"),
    "free rod": lambda: Rod(1.0, 1.0, support="free"),
    "short rod": lambda: Rod(0.3, 0.01, support="fixed"),
}


def truth_of(name, zeta=ZETA):
    return DATASETS[name]().modal_model(N_BAND + N_ABOVE, damping_ratio=zeta, residual=True)


def frf_case(name, noise, seed, *, zeta=ZETA, n_lines=N_LINES):
    """(truth, noisy FRFData, noise-free values); ``zeta``, ``n_lines`` vary the case."""
    truth = truth_of(name, zeta)
    wn = truth.modes["omega_n"].to_numpy()
    fmax = 0.5 * (wn[N_BAND - 1] + wn[N_BAND]) / (2 * np.pi)
    freq = np.linspace(fmax / n_lines, fmax, n_lines)
    exact = truth.frf(2 * np.pi * freq)
    rng = np.random.default_rng(seed)
    noisy = exact * (1 + noise * (rng.normal(size=freq.size)
                                  + 1j * rng.normal(size=freq.size)) / np.sqrt(2))
    return truth, FRFData(freq, noisy), exact


def impulse_case(name, n_samples=8000):
    truth = truth_of(name)
    fs = 2.5 * truth.modes["omega_n"].to_numpy()[-1] / (2 * np.pi)
    t = np.arange(n_samples) / fs
    return truth, t, truth.impulse_response(t)


def mode_errors(truth, model, band_hz, n_truth=N_BAND):
    """Worst relative errors over the band's modes, and the count of bad modes.

    The identified modes in ``band_hz`` are compared with the truth's first ``n_truth``
    (its modes in the band; all 18 for ERA). A truth mode is matched by the identified
    mode nearest in frequency and missed when that one is more than 2 % away; identified
    modes left unmatched are spurious; unstable or negative-mass modes are bad too.
    Errors are over the first ``N_BAND`` (the targets' modes).
    """
    tm = truth.modes.iloc[:n_truth]
    im = model.modes
    im = im[(im["frequency_hz"] >= band_hz[0]) & (im["frequency_hz"] <= band_hz[1])]
    df = dz = dr = 0.0
    bad, used = 0, set()
    for k, (_, row) in enumerate(tm.iterrows()):
        if im.empty:
            bad += 1
            continue
        j = int(np.argmin(np.abs(im["omega_n"].to_numpy() - row["omega_n"])))
        ident = im.iloc[j]
        err_f = abs(ident["omega_n"] / row["omega_n"] - 1)
        if err_f > 0.02 or j in used:
            bad += 1
            continue
        used.add(j)
        if k < N_BAND:
            df = max(df, err_f)
            dz = max(dz, abs(ident["damping_ratio"] / row["damping_ratio"] - 1))
            dr = max(dr, abs(ident["residue"] / row["residue"] - 1))
    bad += len(im) - len(used)
    bad += int(np.sum(im["damping_ratio"] <= 0) + np.sum(im["modal_mass"] <= 0))
    return df, dz, dr, bad


def floor_fit(truth, data):
    """The right model from the true values, same refinement (1/|H_model| weights)."""
    poles = truth.poles[np.argsort(np.abs(truth.poles))][:N_BAND + 2]
    omega, h = data.omega, data.values
    terms = Terms(np.zeros(0), truth.inverse_mass > 0, True)
    lo = np.r_[np.zeros(N_BAND), omega[-1], omega[-1]]
    w = 1 / np.abs(h)
    for _ in range(3):
        poles, x, _ = refine_varpro(omega, h, w, poles, terms, imag_lo=lo, with_std=False)
        r, _, u, d = split_coefficients(x, poles.size, terms)
        model = ModalModel(poles=poles, residues=r, inverse_mass=max(u, 0), flexibility=d)
        w = 1 / np.abs(model.frf(omega))
    return model


def run_frf(name, noise, seeds, method="lscf", floor=False):
    rows = []
    for seed in seeds:
        truth, data, exact = frf_case(name, noise, seed)
        if floor:
            start = time.process_time()
            model = floor_fit(truth, data)
            elapsed = time.process_time() - start
            converged = True
        else:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                start = time.process_time()
                fit = ModalFit(method=method).fit(data)
                elapsed = time.process_time() - start
            model, converged = fit.model_, fit.report_["converged"]
        band = (data.freq_hz[0], data.freq_hz[-1])
        df, dz, dr, bad = mode_errors(truth, model, band)
        fitted = model.frf(data.omega)
        nr_data = np.linalg.norm(fitted - data.values) / np.linalg.norm(data.values)
        nr_true = np.linalg.norm(fitted - exact) / np.linalg.norm(exact)
        rel_true = np.sqrt(np.mean(np.abs(fitted / exact - 1) ** 2))
        dm = abs(truth.inverse_mass / model.inverse_mass - 1) if truth.inverse_mass else (
            np.inf if model.inverse_mass else 0.0)
        rows.append((df, dz, dr, dm, nr_data, nr_true, bad, elapsed, converged, rel_true))
    return rows


def run_era(name):
    truth, t, h = impulse_case(name)
    start = time.process_time()
    fit = ModalFit(method="era").fit((t, h))
    elapsed = time.process_time() - start
    df, dz, dr, bad = mode_errors(truth, fit.model_, (0.0, np.inf), N_BAND + N_ABOVE)
    dm = abs(truth.inverse_mass / fit.model_.inverse_mass - 1) if truth.inverse_mass else (
        np.inf if fit.model_.inverse_mass else 0.0)
    return [(df, dz, dr, dm, fit.report_["impulse_nrmse"], np.nan, bad, elapsed, True,
             np.nan)]


def _max(v):
    v = np.asarray(v, float)
    return np.nan if np.all(np.isnan(v)) else float(np.nanmax(v))


def _num(v, fmt, width):
    return f"{'n/a' if np.isnan(v) else format(v, fmt):>{width}s}"


def summarize(label, name, rows):
    """Print one table row; return its worst ``df``, ``dz``, ``dr`` and ``bad``."""
    a = np.array([r[:8] + r[9:] for r in rows], dtype=float)
    conv = [r[8] for r in rows]
    conv = "-" if any(c is None for c in conv) else ("yes" if all(conv) else "NO")
    dm = _max(a[:, 3])
    df, dz, dr = _max(a[:, 0]), _max(a[:, 1]), _max(a[:, 2])
    dm_txt = "n/a" if np.isnan(dm) else ("-" if dm == 0 else f"{dm:.1e}")
    print(f"| {name:9s} | {label:18s} | {_num(df, '8.2e', 8)} | {_num(dz, '8.2e', 8)} | "
          f"{_num(dr, '8.2e', 8)} | {dm_txt:>7s} | "
          f"{_num(_max(a[:, 4]), '6.4f', 6)} | {_num(_max(a[:, 5]), '6.4f', 6)} | "
          f"{_num(_max(a[:, 8]), '6.4f', 6)} | "
          f"{int(a[:, 6].sum()):3d} | {np.median(a[:, 7]):6.3f} | {conv:4s} |")
    return {"df": df, "dz": dz, "dr": dr, "bad": int(a[:, 6].sum())}


# ------------------------------------------------------------------ anchors
def anchor_fitters():
    """(label, kind, runner) of the anchors of ``anchors.py``, told the model as there.

    ``kind`` is ``"frf"`` (runner(truth, FRFData) -> (poles, residues, seconds)) or
    ``"ir"`` (runner(truth, t, h) -> same).
    """
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import anchors

    def vf(n_real):
        return lambda truth, data: anchors.skrf_vector_fit(data, N_BAND, n_poles_real=n_real)

    def ema(fn):
        return lambda truth, data: fn(
            data, N_BAND, approx_freq_hz=truth.modes["frequency_hz"].to_numpy()[:N_BAND])

    def era(hankel):
        return lambda truth, t, h: anchors.control_era(
            t, h, truth.n_modes, rigid_body=truth.inverse_mass > 0, hankel=hankel)

    return [("skrf VF0", "frf", vf(0)), ("skrf VF2", "frf", vf(2)),
            ("sdypy LSCF", "frf", ema(anchors.sdypy_lscf)),
            ("sdypy LSCE", "frf", ema(anchors.sdypy_lsce)),
            ("ctrl ERA 2r", "ir", era(None)), ("ctrl ERA 500", "ir", era(500))]


FAILURES = []


def _anchor_row(label, name, truth, runner, args, band, n_truth):
    """Run one anchor fit and score it like a ModalFit row (modes only: no nrmse/dM)."""
    dm = np.nan if truth.inverse_mass else 0.0
    start = time.process_time()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            p, r, _ = runner(truth, *args)
        elapsed = time.process_time() - start
        model = ModalModel(poles=p, residues=r)
    except Exception as exc:  # noqa: BLE001 - an anchor that fails is a result too
        FAILURES.append(f"{label} on {name}: {type(exc).__name__}: {exc}")
        return (np.nan, np.nan, np.nan, dm, np.nan, np.nan, N_BAND,
                time.process_time() - start, None, np.nan)
    df, dz, dr, bad = mode_errors(truth, model, band, n_truth)
    return (df, dz, dr, dm, np.nan, np.nan, bad, elapsed, None, np.nan)


def run_anchor_frf(label, name, noise, seeds, runner):
    rows = []
    for seed in (seeds if noise else list(seeds)[:1]):
        truth, data, _ = frf_case(name, noise, seed)
        rows.append(_anchor_row(label, name, truth, runner, (data,),
                                (data.freq_hz[0], data.freq_hz[-1]), N_BAND))
    return rows


def run_anchor_era(label, name, runner):
    truth, t, h = impulse_case(name)
    return [_anchor_row(label, name, truth, runner, (t, h), (0.0, np.inf),
                        N_BAND + N_ABOVE)]


def compare_at_5(results, datasets):
    """Closing lines: ModalFit's worst-mode errors vs the best anchor's, 5 % noise."""
    print("\nworst-mode errors at 5 % noise (worst over seeds and the 8 modes), ModalFit "
          "(lscf) vs the best anchor per metric among anchors with bad = 0 "
          "(* : none had bad = 0, best of all); ratio < 1: ModalFit better")
    for name in datasets:
        ours = results[(name, "lscf 5%")]
        cands = {lab[:-3]: v for (n, lab), v in results.items()
                 if n == name and lab.endswith(" 5%") and lab[:-3] in ANCHOR_LABELS}
        clean = {k: v for k, v in cands.items() if v["bad"] == 0}
        pool, star = (clean, "") if clean else (cands, "*")
        parts = []
        for key in ("df", "dz", "dr"):
            finite = {k: v[key] for k, v in pool.items() if np.isfinite(v[key])}
            if not finite:
                parts.append(f"{key} {ours[key]:.1e} vs n/a")
                continue
            best = min(finite, key=finite.get)
            parts.append(f"{key} {ours[key]:.1e} vs {finite[best]:.1e} ({best}{star}, "
                         f"ratio {ours[key] / finite[best]:.2g})")
        print(f"  {name:9s} (ModalFit bad {ours['bad']}): " + "; ".join(parts))


ANCHOR_LABELS = set()


def worst_modes(seeds, noise=0.05):
    """Per mode, at ``noise``: the worst errors over the seeds and the mean standard
    deviation the fit reports (its own uncertainty), in units of 1e-4 (df) and % (dz)."""
    print(f"\nper mode at {noise:.0%} noise, worst over the seeds (fit's reported std):")
    for name in ("beam", "fixed rod", "free rod"):
        errs, stds = [], []
        for seed in seeds:
            truth, data, _ = frf_case(name, noise, seed)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                modes = ModalFit().fit(data).report_["modes"].iloc[:N_BAND]
            tm = truth.modes.iloc[:N_BAND]
            errs.append(np.r_[np.abs(modes["omega_n"].to_numpy() / tm["omega_n"].to_numpy() - 1),
                              np.abs(modes["damping_ratio"].to_numpy()
                                     / tm["damping_ratio"].to_numpy() - 1)])
            stds.append(np.r_[modes["frequency_hz_std"] / modes["frequency_hz"],
                              modes["damping_ratio_std"] / modes["damping_ratio"]])
        e, sd = np.max(errs, axis=0), np.mean(stds, axis=0)
        print(f"  {name:9s} df [1e-4]: " + " ".join(f"{1e4 * a:.1f}({1e4 * b:.1f})"
                                                   for a, b in zip(e[:N_BAND], sd[:N_BAND])))
        print(f"  {'':9s} dz [%]:    " + " ".join(f"{100 * a:.1f}({100 * b:.1f})"
                                                   for a, b in zip(e[N_BAND:], sd[N_BAND:])))


TARGETS_5 = {"df": 5e-4, "dz": 5e-2, "dr": 1e-2, "dM": 1e-2, "nrmse": 2e-2}


def information_bound(n_seeds, noise=0.05, n_check=20, draws=20000):
    """What the noise allows: the Cramer-Rao bound beside the measured errors.

    For each dataset at ``noise``: from ``identification_bound.bound_draws`` (an efficient
    fit, linearised), the median over benchmark runs of the worst-of-``n_seeds`` errors and
    the probability that one run of ``n_seeds`` seeds meets each target and all of them;
    then, to check the linearisation, the per-seed medians of the worst-mode ``df`` and of
    ``vs true`` over seeds ``0..n_check-1``: bound, ``floor`` fit, ``ModalFit()``.
    """
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import identification_bound as ib

    rng = np.random.default_rng(12345)
    keys = list(TARGETS_5)
    print(f"\ninformation bound at {noise:.0%} noise (Cramer-Rao, any unbiased fit of the "
          f"floor's model; {draws} draws): median of the worst over {n_seeds} seeds, and "
          f"P = probability that a run of {n_seeds} seeds meets the target")
    print("| dataset   | " + " | ".join(f"{k} (target {TARGETS_5[k]:g})" for k in keys)
          + " | P(all) |")
    print("|---|" + "---|" * (len(keys) + 1))
    checks = []
    for name in DATASETS:
        truth, data, exact = frf_case(name, 0.0, 0)
        d = ib.bound_draws(truth, data.omega, exact, noise, n_modes=N_BAND + 2,
                           n_band=N_BAND, draws=draws, rng=rng)
        stats, p_all = ib.runs_meeting(d, TARGETS_5, n_seeds)
        cells = [("-" if not np.any(d[k]) else f"{stats[k][0]:.2g}, P {stats[k][1]:.2f}")
                 for k in keys]
        print(f"| {name:9s} | " + " | ".join(f"{c:>17s}" for c in cells) + f" | {p_all:6.3f} |")
        floor = np.array(run_frf(name, noise, range(n_check), floor=True), dtype=float)
        fit = np.array(run_frf(name, noise, range(n_check)), dtype=float)
        checks.append((name, np.median(d["df"]), np.median(floor[:, 0]), np.median(fit[:, 0]),
                       np.median(d["nrmse"]), np.median(floor[:, 5]), np.median(fit[:, 5])))
    print(f"per-seed medians over seeds 0..{n_check - 1} (bound / floor fit / ModalFit):")
    for name, *v in checks:
        print(f"  {name:9s} df {v[0]:.2e} / {v[1]:.2e} / {v[2]:.2e};  "
              f"vs true {v[3]:.4f} / {v[4]:.4f} / {v[5]:.4f}")


def bound_sweep(noise=0.05, n_seeds=5, draws=20000):
    """The beam's bound over damping ratios and line counts (the benchmark's other inputs
    fixed): which data would let an efficient fit meet every 5 % target
    (``identification_bound.bound_draws``)."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import identification_bound as ib

    rng = np.random.default_rng(12345)
    print(f"beam tip, {noise:.0%} noise, Cramer-Rao bound: median worst of {n_seeds} seeds "
          f"and P(a run of {n_seeds} seeds meets the target)")
    print("| zeta | lines | df | dz | dr | nrmse (vs true) | P(all) |")
    print("|---|---|---|---|---|---|---|")
    cases = [(z, N_LINES) for z in (0.002, 0.005, 0.01, 0.02, 0.05)]
    cases += [(ZETA, n) for n in (2000, 8000, 16000, 32000)]
    for zeta, n_lines in cases:
        truth, data, exact = frf_case("beam", 0.0, 0, zeta=zeta, n_lines=n_lines)
        d = ib.bound_draws(truth, data.omega, exact, noise, n_modes=N_BAND + 2,
                           n_band=N_BAND, draws=draws, rng=rng)
        stats, p_all = ib.runs_meeting(d, {k: TARGETS_5[k] for k in ("df", "dz", "dr",
                                                                      "nrmse")}, n_seeds)
        cells = " | ".join(f"{median:.2g} (P {p:.2f})" for median, p in stats.values())
        print(f"| {zeta:g} | {n_lines} | {cells} | {p_all:.3f} |")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--quick", action="store_true", help="5 %% noise and LSCF only")
    parser.add_argument("--anchors", action="store_true",
                        help="also run the anchors of anchors.py on the same data "
                             "(needs the bench extra)")
    parser.add_argument("--anchor-seeds", type=int, default=None,
                        help="seeds 0..N-1 for the anchors (default: --seeds)")
    parser.add_argument("--bound-sweep", action="store_true",
                        help="only the beam's Cramer-Rao bound over damping and line count")
    args = parser.parse_args(argv)
    if args.bound_sweep:
        bound_sweep(n_seeds=args.seeds)
        return
    seeds = range(args.seeds)
    anchor_seeds = range(args.seeds if args.anchor_seeds is None else args.anchor_seeds)
    t_start = time.perf_counter()
    print(f"BLAS threads {os.environ.get('OPENBLAS_NUM_THREADS')}, cpus {os.cpu_count()}, "
          f"load average {os.getloadavg()[0]:.2f}; {args.seeds} seeds; targets at 5 % noise: "
          + ", ".join(f"{k.replace('nrmse', 'nrmse (truth)')} < {v:g}"
                      for k, v in TARGETS_5.items())
          + ", bad = 0, t < 0.1 s; clean: df < 1e-5, dz < 1e-3, dr < 1e-3")
    fitters = []
    if args.anchors:
        fitters = anchor_fitters()
        ANCHOR_LABELS.update(label for label, _, _ in fitters)
        versions = []
        for mod in ("skrf", "sdypy.EMA", "control"):
            try:
                m = __import__(mod, fromlist=["_"])
                versions.append(f"{mod} {getattr(m, '__version__', '?')}")
            except ImportError:
                versions.append(f"{mod} missing (pip install -e .[bench])")
        print(f"anchors ({', '.join(versions)}) on the same data: FRF anchors told the 8 "
              f"in-band modes, seeds 0..{len(anchor_seeds) - 1} (noise 0: seed 0 only), "
              "ERA anchors told the truth's 18 modes (+ rigid body) on the era-clean record; "
              "anchors return modes only: dM, nrmse, vs true, rel n/a")
    print("| dataset   | fit                | df       | dz       | dr       | dM      | "
          "nrmse  | vs true| rel    | bad | t (s)  | conv |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    ModalFit().fit(frf_case("fixed rod", 0.05, 0)[1])          # warm-up (imports)
    run_era("fixed rod")
    for _, kind, runner in fitters:                            # warm-up (imports)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                if kind == "frf":
                    truth, data, _ = frf_case("fixed rod", 0.05, 0)
                    runner(truth, data)
                else:
                    runner(*impulse_case("fixed rod"))
            except Exception:  # noqa: BLE001
                pass
    noises = (0.05,) if args.quick else (0.0, 0.01, 0.05)
    results = {}
    for name in DATASETS:
        for noise in noises:
            label = f"lscf {noise:.0%}"
            results[(name, label)] = summarize(label, name, run_frf(name, noise, seeds))
        if not args.quick:
            summarize("floor 5%", name, run_frf(name, 0.05, seeds, floor=True))
            summarize("vf 5%", name, run_frf(name, 0.05, seeds, method="vf"))
            summarize("era clean", name, run_era(name))
        for alabel, kind, runner in fitters:
            if kind == "frf":
                for noise in noises:
                    label = f"{alabel} {noise:.0%}"
                    results[(name, label)] = summarize(
                        label, name, run_anchor_frf(alabel, name, noise, anchor_seeds, runner))
            elif not args.quick:
                summarize(f"{alabel} clean", name, run_anchor_era(alabel, name, runner))
    for line in FAILURES:
        print(f"  failed: {line}")
    if fitters:
        compare_at_5(results, DATASETS)
    if not args.quick:
        worst_modes(seeds)
        information_bound(args.seeds)
    print(f"total {time.perf_counter() - t_start:.0f} s; "
          f"load average at the end: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
