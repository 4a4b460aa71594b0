"""Third-party anchors for the identification benchmark: what a user would otherwise run.

Run:  python benchmarks/anchors.py [--seeds N] [--quick]

Needs the optional ``bench`` extra (``pip install -e .[bench]``: scikit-rf, sdypy-EMA;
python-control is already a runtime dependency). Prints a table and exits; it asserts
nothing. The data and the metrics are those of ``identification_data.py``:
``make_case`` (4000-line receptance, 8 modes in band, ``zeta = 0.01``, proportional complex
noise) for the frequency-domain anchors and ``make_impulse_case`` (8000 samples at
``fs = 4 f_9``, noise ``eta * rms(h)``) for ERA.

Every anchor is *told the model order* and returns ``(poles, residues, seconds)``: one
pole of each complex pair (``Im p > 0``, rad/s) and its residue in the convention
``H(s) = sum r/(s - p) + conj(r)/(s - conj(p)) (+ rigid/constant terms)``, which is
modalid's (:class:`modalid.ModalModel`); ``seconds`` is the wall time of the anchor's own
calls and of the conversion.

Anchors and the exact calls
---------------------------
:func:`skrf_vector_fit` - scikit-rf's vector fitting on a 1-port ``Network`` whose
    S-parameter is the receptance (VectorFitting fits whatever ``network.s`` holds; the
    passivity check it runs after the fit is irrelevant here and its warning is silenced)::

        nw = skrf.Network(frequency=skrf.Frequency.from_f(f_hz, unit="Hz"), s=H[:, None, None])
        vf = skrf.vectorFitting.VectorFitting(nw)
        vf.vector_fit(n_poles_real=n_real, n_poles_cmplx=n_modes, fit_constant=True)

    ``vf.poles`` are in rad/s (one per complex pair, ``Im > 0``) and ``vf.residues[0]`` are
    already in modalid's convention (``get_model_response`` evaluates
    ``r/(s-p) + conj(r)/(s-conj(p)) + d`` at ``s = 2 pi j f``). Real poles are dropped from
    the returned modes. ``enforce_dc`` only acts when the first line is 0 Hz (not here).

:func:`sdypy_lscf` / :func:`sdypy_lsce` - sdypy-EMA's LSCF or LSCE poles, picked at the
    told natural frequencies, then LSFD modal constants with lower and upper residuals::

        m = sdypy.EMA.Model(frf=H, freq=k * f_hz, lower=k * f_hz[0], upper=k * f_hz[-1],
                            pol_order_high=30, frf_form="receptance")
        m.get_poles(method="lscf")            # or "lsce"
        m.select_closest_poles(k * f_told)    # default f_window=50, fn_temp=1e-3, xi_temp=0.05
        H_rec, A = m.get_constants(method="lsfd")
        p = [m.all_poles[i][j] for i, j in m.pole_ind] / k;  r = A[0] / k

    sdypy's receptance LSFD model is ``A/(j w - p) + conj(A)/(j w - conj(p)) - LR/w^2 + UR``
    (see ``LSFD`` and ``FRF_reconstruct``), so ``A`` is our ``r`` (conjugated together with
    ``p`` when ``Im p < 0``) and ``LR`` is the rigid-body ``1/M``. ``lower`` must be > 0:
    with ``lower = 0`` the lower-residual column ``-1/w^2`` is infinite at the 0 Hz line
    LSCF prepends, and ``lstsq`` fails ("SVD did not converge").

    Frequency scaling ``k``: ``select_closest_poles`` searches stable poles in *absolute*
    windows (``f_window = 50`` Hz halved step by step, always ending with a 2 Hz window)
    and the stabilization merges poles closer than an absolute 1e-3 Hz. Our unit models
    have modes 0.25 Hz apart (rods) and a first mode at 0.56 Hz (cantilever), where those
    windows average several modes together (every pick wrong on the rods, 1-5 of 8 wrong on
    the cantilever). The anchor therefore runs on the frequency axis scaled by
    ``k = 100 Hz / min gap`` of ``[0, f_told]`` (an exact change of time unit: ``H`` is
    unchanged, ``p`` and ``r`` scale by ``k``) and scales back. Without it, the table would
    measure the window, not LSCF.

:func:`control_era` - python-control's eigensystem realization on the Markov parameters
    ``h * dt`` of the sampled impulse response::

        sysd, S = control.eigensys_realization(h * dt, 2 * n_modes + 2 * rigid, dt=dt
                                               [, m=hankel, n=hankel])
        z = numpy.linalg.eigvals(sysd.A);  p = log(z) / dt

    then the residues by linear least squares of ``h`` on ``2 Re(r z^k)`` (complex ``z``),
    ``c z^k`` (real ``z``) and, with a rigid body, ``u t`` (the two eigenvalues nearest
    ``z = 1`` are its double pole and are replaced by that column). python-control's
    default Hankel size is ``m = n = 2 r`` (only the first ``4 r + 1`` samples are used).
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import contextlib  # noqa: E402
import io  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from identification_data import (CASES, make_case, make_impulse_case,  # noqa: E402
                                 mode_errors)

__all__ = ["skrf_vector_fit", "sdypy_lscf", "sdypy_lsce", "control_era"]


def _upper_half(p, r):
    """One pole of each pair with ``Im p > 0`` (residue conjugated with it)."""
    p = np.asarray(p, dtype=complex)
    r = np.asarray(r, dtype=complex)
    flip = p.imag < 0
    return np.where(flip, p.conj(), p), np.where(flip, r.conj(), r)


# ------------------------------------------------------------------ scikit-rf
def skrf_vector_fit(frf, n_modes, *, n_poles_real=0, fit_constant=True):
    """scikit-rf ``VectorFitting`` with ``n_modes`` complex starting poles.

    Parameters
    ----------
    frf : modalid.FRFData
        Receptance (any quantity is fitted as given; the residues are then in its units).
    n_modes : int
        Number of complex-conjugate pole pairs (``n_poles_cmplx``).
    n_poles_real : int
        Number of real starting poles (0 as told; 2 lets it model a rigid body or the
        residual of the modes above the band).
    fit_constant : bool
        Fit the constant term ``d`` (the upper residual).

    Returns
    -------
    poles, residues : ndarray of complex
        The fitted complex poles (``Im > 0``, rad/s) and their residues; real poles dropped.
    seconds : float
    """
    import skrf
    from skrf.vectorFitting import VectorFitting

    t0 = time.perf_counter()
    freq = skrf.Frequency.from_f(np.asarray(frf.freq_hz, float), unit="Hz")
    nw = skrf.Network(frequency=freq, s=np.asarray(frf.values, complex).reshape(-1, 1, 1))
    vf = VectorFitting(nw)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # "fitted network is passive, the fit not"
        vf.vector_fit(n_poles_real=n_poles_real, n_poles_cmplx=n_modes,
                      fit_constant=fit_constant)
    p = np.asarray(vf.poles, complex)
    r = np.asarray(vf.residues, complex)[0]
    keep = p.imag != 0
    p, r = _upper_half(p[keep], r[keep])
    return p, r, time.perf_counter() - t0


# ------------------------------------------------------------------ sdypy-EMA
def _peak_frequencies(frf, n_modes):
    from scipy.signal import find_peaks

    mag = np.abs(frf.values)
    peaks, props = find_peaks(mag, prominence=0)
    best = peaks[np.argsort(props["prominences"])[::-1][:n_modes]]
    return np.sort(np.asarray(frf.freq_hz)[best])


def _sdypy(frf, n_modes, method, approx_freq_hz, pol_order_high, freq_scale):
    from sdypy import EMA

    f_hz = np.asarray(frf.freq_hz, float)
    h = np.asarray(frf.values, complex)
    if approx_freq_hz is None:
        approx_freq_hz = _peak_frequencies(frf, n_modes)
    f_told = np.sort(np.asarray(approx_freq_hz, float))
    if f_told.size != n_modes:
        raise ValueError(f"approx_freq_hz must hold n_modes = {n_modes} frequencies, "
                         f"got {f_told.size}")
    t0 = time.perf_counter()
    k = freq_scale if freq_scale is not None else 100.0 / np.min(np.diff(np.r_[0.0, f_told]))
    # sdypy prints tqdm bars on stderr even with show_progress=False (stabilization) and
    # warns when `upper` equals the last line (it drops that line); silence both.
    with warnings.catch_warnings(), contextlib.redirect_stderr(io.StringIO()):
        warnings.simplefilter("ignore")
        m = EMA.Model(frf=h, freq=k * f_hz, lower=k * f_hz[0], upper=k * f_hz[-1],
                      pol_order_high=pol_order_high, frf_form="receptance")
        m.get_poles(method=method, show_progress=False)
        m.select_closest_poles(k * f_told)
        _, a = m.get_constants(method="lsfd")
    p = np.array([m.all_poles[i][j] for i, j in m.pole_ind], dtype=complex) / k
    r = np.asarray(a, complex)[0] / k
    p, r = _upper_half(p, r)
    return p, r, time.perf_counter() - t0


def sdypy_lscf(frf, n_modes, *, approx_freq_hz=None, pol_order_high=30, freq_scale=None):
    """sdypy-EMA LSCF poles picked at ``approx_freq_hz``, LSFD residues (see module doc).

    Parameters
    ----------
    frf : modalid.FRFData
        Receptance.
    n_modes : int
        Number of modes to pick.
    approx_freq_hz : array_like of float, shape (n_modes,), optional
        The told natural frequencies (Hz); default: the ``n_modes`` most prominent peaks
        of ``|H|``.
    pol_order_high : int
        Highest order of sdypy's stabilization chart.
    freq_scale : float, optional
        Factor applied to the frequency axis (default ``100 Hz / min gap`` of the told
        frequencies and 0, see module doc); ``1`` runs sdypy on the raw axis.

    Returns
    -------
    poles, residues : ndarray of complex, shape (n_modes,)
    seconds : float
    """
    return _sdypy(frf, n_modes, "lscf", approx_freq_hz, pol_order_high, freq_scale)


def sdypy_lsce(frf, n_modes, *, approx_freq_hz=None, pol_order_high=30, freq_scale=None):
    """sdypy-EMA LSCE poles picked at ``approx_freq_hz``, LSFD residues; as :func:`sdypy_lscf`."""
    return _sdypy(frf, n_modes, "lsce", approx_freq_hz, pol_order_high, freq_scale)


# ------------------------------------------------------------------ python-control
def control_era(t, h, n_modes, *, rigid_body=False, hankel=None):
    """python-control ERA of order ``2 n_modes (+2)``; residues by least squares.

    Parameters
    ----------
    t, h : array_like of float
        Equally spaced sample times (s) and impulse-response samples.
    n_modes : int
        Number of complex mode pairs in the realization.
    rigid_body : bool
        Add 2 to the order for the rigid-body double pole at 0 and fit ``u t``.
    hankel : int, optional
        Hankel rows and columns ``m = n`` (default: python-control's ``2 * order``).

    Returns
    -------
    poles, residues : ndarray of complex
        Complex poles (``Im > 0``, rad/s) of the realization, less the rigid-body pair.
    seconds : float
    """
    import control

    t = np.asarray(t, float)
    h = np.asarray(h, float)
    t0 = time.perf_counter()
    dt = float(t[1] - t[0])
    order = 2 * n_modes + (2 if rigid_body else 0)
    kw = {} if hankel is None else {"m": int(hankel), "n": int(hankel)}
    sysd, _ = control.eigensys_realization(h * dt, order, dt=dt, **kw)
    z = np.linalg.eigvals(np.asarray(sysd.A)).astype(complex)
    if rigid_body:
        drop = np.argsort(np.abs(z - 1.0))[:2]
        z = np.delete(z, drop)
    tol = 1e-10 * max(1.0, float(np.max(np.abs(z)))) if z.size else 0.0
    zc = z[z.imag > tol]
    zr = z[np.abs(z.imag) <= tol].real
    k = np.round((t - t[0]) / dt)
    cols = []
    for zz in zc:
        e = zz ** k * np.exp(np.log(zz) * t[0] / dt)
        cols += [2.0 * e.real, -2.0 * e.imag]          # 2 Re(r e) = 2 (Re r Re e - Im r Im e)
    for zz in zr:
        cols.append(np.sign(zz) ** k * np.abs(zz) ** (k + t[0] / dt))
    if rigid_body:
        cols.append(t)
    if cols:
        a = np.stack(cols, axis=1)
        scale = np.linalg.norm(a, axis=0)
        scale[scale == 0] = 1.0
        x = np.linalg.lstsq(a / scale, h, rcond=None)[0] / scale
    else:
        x = np.zeros(0)
    nc = zc.size
    r = x[0:2 * nc:2] + 1j * x[1:2 * nc:2]
    with np.errstate(divide="ignore"):
        p = np.log(zc) / dt
    return p, r, time.perf_counter() - t0


# ------------------------------------------------------------------ table
def _anchors(quick):
    """(label, data kind, runner(case data) -> (p, r, seconds))."""
    def vf(n_real):
        return lambda d: skrf_vector_fit(d["frf"], d["n"], n_poles_real=n_real)

    def ema(fn):
        return lambda d: fn(d["frf"], d["n"], approx_freq_hz=d["f_told"])

    def era(hankel):
        return lambda d: control_era(d["t"], d["h"], d["n_order"], rigid_body=d["rigid"],
                                     hankel=hankel)

    out = [("skrf VF (0 real)", "frf", vf(0)),
           ("skrf VF (2 real)", "frf", vf(2)),
           ("sdypy LSCF+LSFD", "frf", ema(sdypy_lscf)),
           ("sdypy LSCE+LSFD", "frf", ema(sdypy_lsce)),
           ("control ERA (m=n=2r)", "ir", era(None)),
           ("control ERA (m=n=500)", "ir", era(500))]
    return out[::2] + out[5:] if quick else out


def _fmt(v, pct=True):
    if v is None or not np.isfinite(v):
        return "-"
    if pct:
        v = 100.0 * v
        return f"{v:.2g}" if v < 10 else f"{v:.0f}"
    return f"{v:.3g}"


def run(seeds, noises=(0.0, 0.05), quick=False, out=print):
    rows = []
    for label, kind, runner in _anchors(quick):
        for name in CASES:
            for noise in noises:
                errs, times, fails = [], [], 0
                # noise-free data do not depend on the seed: one run, not len(seeds) copies
                for seed in (seeds if noise else list(seeds)[:1]):
                    if kind == "frf":
                        truth, frf, tm = make_case(name, noise=noise, seed=seed)
                        d = {"frf": frf, "n": len(tm),
                             "f_told": tm["frequency_hz"].to_numpy()}
                    else:
                        truth, t, h, tm = make_impulse_case(name, noise=noise, seed=seed)
                        d = {"t": t, "h": h, "n_order": truth.n_modes,
                             "rigid": truth.inverse_mass > 0}
                    try:
                        with warnings.catch_warnings():
                            warnings.simplefilter("ignore")
                            p, r, sec = runner(d)
                    except Exception as exc:  # noqa: BLE001 - an anchor that crashes is a result too
                        fails += 1
                        out(f"  [{label} {name} noise={noise} seed={seed}] failed: "
                            f"{type(exc).__name__}: {exc}")
                        continue
                    errs.append(mode_errors(tm, p, r))
                    times.append(sec)
                rows.append((label, name, noise, errs, times, fails))
                _print_row(rows[-1], out)
    return rows


_HEADER = ("| anchor | case | noise | f err % med/max | zeta err % med/max | r err % med/max "
           "| missed | spurious | unstable | neg. mass | fails | time s (median) |")


def _print_row(row, out):
    label, name, noise, errs, times, fails = row

    def medmax(key):
        v = np.array([e[key] for e in errs], float)
        if v.size == 0 or np.all(np.isnan(v)):
            return "-"
        return f"{_fmt(np.nanmedian(v))} / {_fmt(np.nanmax(v))}"

    def total(key):
        return str(sum(e[key] for e in errs))

    t = _fmt(float(np.median(times)), pct=False) if times else "-"
    out(f"| {label} | {name} | {noise:g} | {medmax('freq_err')} | {medmax('damp_err')} | "
        f"{medmax('res_err')} | {total('missed')} | {total('spurious')} | "
        f"{total('unstable')} | {total('neg_mass')} | {fails} | {t} |")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=5, help="noise seeds 0..N-1 (default 5)")
    ap.add_argument("--quick", action="store_true",
                    help="one variant per anchor family, 2 seeds")
    args = ap.parse_args(argv)
    n_seeds = 2 if args.quick and args.seeds == 5 else args.seeds
    seeds = range(n_seeds)
    versions = []
    for mod in ("numpy", "scipy", "skrf", "sdypy.EMA", "control"):
        try:
            m = __import__(mod, fromlist=["_"])
            versions.append(f"{mod} {getattr(m, '__version__', '?')}")
        except ImportError:
            versions.append(f"{mod} missing (pip install -e .[bench])")
    print("anchors: " + ", ".join(versions))
    print(f"seeds 0..{n_seeds - 1}; BLAS threads {os.environ.get('OPENBLAS_NUM_THREADS')}, "
          f"cpus {os.cpu_count()}, load average {os.getloadavg()[0]:.2f}")
    print("errors: worst mode of each run (relative, %), then median / max over seeds; "
          "counts summed over seeds (noise 0: one run, the data do not depend on the seed); "
          "a true mode is missed when no pole is within "
          "1 % of it (its errors are then not in the worst); spurious = unmatched poles "
          "in band; unstable (Re p > 0) and neg. mass (-1/(2 Im p Im r) < 0) count poles in band")
    print("FRF anchors: make_case (4000 lines, 8 modes in band, told the 8 modes); "
          "ERA: make_impulse_case (8000 samples, fs = 4 f9; told the truth's 18 modes "
          "(+ rigid body), since all 18 are in h, 6 of the cantilever's aliased)")
    print()
    print(_HEADER)
    print("|" + "---|" * 12)
    t0 = time.perf_counter()
    run(seeds, quick=args.quick)
    print()
    print(f"total {time.perf_counter() - t0:.0f} s; load average at the end "
          f"{os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
