"""Impact predictions from synthetic hammer tests against the exact continuum answers.

For each case two bodies collide (rigid or Hertz contact, both at rest inside, touching at
``t = 0``). Every continuum (rod, cantilever) is *measured*: a synthetic hammer test on
its lightly damped truth, an H1 estimate, a :class:`modalid.ModalFit`; a lumped mass (a
striker, a ball) is known exactly. The identified models are continued above their band
and the impact is predicted; the prediction is compared with the exact solution on the
exact (undamped, untruncated) models.

Measurement (:class:`Measurement`, the defaults are the benchmark's):

* truth ``data_synth.lightly_damped(body, n + 10, zeta)`` with ``zeta = 1e-4`` for every
  mode (metal rods and beams: 1e-4..1e-3; with 1e-3 the structure's own damping takes
  0.6 % off the equal rods' restitution, whose exact answer is the undamped continuum's)
  and the omitted modes' static flexibility;
* ``data_synth.synthetic_hammer_test``: velocity response (a laser vibrometer), 5 hits,
  half-sine ``0.5 / f_top`` long, ``fs = 5 f_top``, the analyser's anti-aliasing filter,
  white noise of ``noise x rms(record)`` on both channels (``noise_reference="rms"``: the
  H1 estimates then carry about ``noise`` of error per line, the ``frf_noise_%`` column;
  ``"max"`` gave them 8-9 times that); ``f_top`` is midway between elastic modes ``n``
  and ``n + 1`` (the band covers ``n`` modes);
* record ``min(50 / f1, max(4000 / f_top, 5 / f1))`` long (50 periods of the first
  elastic mode, at most 4000 lines in the band unless fewer than 5 periods of mode 1
  fit: a beam's ``f_top / f1`` grows like ``n**2``, 5600 lines at 20 modes and 22 500 at
  40; with 3.6 periods mode 1 came out 1.4 % high, with 5 to 0.005 %), an exponential
  window ending at 1 % (``sigma_w = 4.6 / duration``) so the record needs not outlast
  the ``1/(zeta w1)`` decay: the resolution needed is then the *windowed* half-power
  bandwidth ``2 (zeta w + sigma_w)``;
* ``modalid.frf_from_hammer`` (force window, exponential window), the band from one line
  spacing to ``f_top``, ``ModalFit(weighting="noise", **est.fit_options())``: the
  windowed, truncated FRF modelled exactly (poles moved by ``-sigma_w``, each residue
  scaled by the record's end, the rigid line ``1/(M (s + sigma_w)^2)``) and the
  structure's model returned.

Identification: ``ModalFit(weighting="noise", max_order=fit_max_order(n), ...)``: above
26 modes the stabilization diagram goes to order ``4 n + 16`` (``ModalFit``'s default caps
it at 120, which found 9 of a fixed rod's 40 modes), except for bands of 8000 lines or more,
fitted by segments of a few modes each (:func:`fit_max_order`).

Prediction: ``identified_model`` (normal modes, ``continue_above_band`` to
``tail_extent(n)`` times the band top), ``solve_impact(method="laplace")`` with at most
200 000 output samples (``"modal"`` with ``dt = dt_exact`` for Hertz contact); figures by
``impact_figures`` with contacts closer than ``1/(2 f_top)`` merged (ringing after a
separation aside). Uncertainty, at every band: ``uncertainty_band`` (stated level 0.9 for
the four figures together: 4 draws of the fits' residues and 4 of their poles,
re-identification on 80 % of each band, the tail to half its extent).
:func:`run_benchmark` identifies each measured body once per band and noise (with its
cut-band re-identification) and computes each exact reference once, then predicts each
case at each band in a task of its own. Targets:
:data:`TARGETS` (1 % noise), :data:`TARGETS_5` (5 %) for every case and band,
:data:`BAND_TARGET`.

Exact references (:func:`exact_reference`): ``mass_on_fixed_rod`` (closed form, every
contact) and ``two_free_rods_equal_transit`` (closed form); otherwise ``solve_impact(...,
method="convolution")`` on the exact models with the step of each case (``dt_exact``,
chosen so that halving it changes no figure by more than 0.05 %, the rod-cantilever's
peak force by 0.14 %); the Hertz ball's figures extrapolated to ``dt = 0`` from ``dt_exact``
and its half, its duration measured where the gap crosses zero
(:func:`impactpred._benchmark_cases.gap_crossing_duration`), not on the grid.
"""

from __future__ import annotations

import math
import sys
import time
import warnings
from contextlib import closing
from pathlib import Path

import numpy as np
import pandas as pd

from data_synth import CantileverBeam, Rod

from .api import choose_dt, solve_impact
from .body import Body
from .contact import Rigid
from .parallel import check_executor, progress_bar, resolve_executor
from .truncation import (
    FIGURES,
    band_resolution,
    continue_above_band,
    identified_model,
    impact_figures,
    tail_extent,
)
from .uncertainty import refit_on_cut_band, uncertainty_band
from ._benchmark_cases import (Case, Measurement, Reference, benchmark_cases,
                               exact_reference, fit_max_order, measure_body)
from ._benchmark_report import (
    _SHORT,
    BAND_TARGET,
    TARGETS,
    TARGETS_5,
    _markdown,
    _plot,
    check_targets,
    error_table,
    markdown_table,
    targets_at,
)

__all__ = ["BAND_TARGET", "TARGETS", "TARGETS_5", "Case", "Measurement", "Reference",
           "benchmark_cases", "body_seed", "check_targets", "error_table", "exact_reference",
           "fit_max_order", "markdown_table", "measure_body", "run_benchmark", "run_case",
           "targets_at"]


# ---------------------------------------------------------------------- pipeline
def _force_error(result, ref: Reference) -> float:
    """``||f - f_exact|| / ||f_exact||`` (L2 over ``[0, t_end]``, 20001 points)."""
    grid = np.linspace(0.0, ref.t[-1], 20001)
    fe = np.interp(grid, ref.t, ref.force)
    fp = np.interp(grid, result.t, result.force)
    return float(np.linalg.norm(fp - fe) / np.linalg.norm(fe))


#: most output samples of an exact (Laplace) prediction over ``t_end``
_MAX_OUTPUT_SAMPLES = 200_000


def _solver(case, dt=None):
    """``solve(model1, model2) -> ImpactResult`` of ``case``: the exact solver for a linear
    contact, else ``"modal"`` at ``case.dt_exact``. The exact solver's output step is its
    automatic one (``choose_dt``: 8 samples per ``1/omega`` of the fastest pole), but at
    most ``_MAX_OUTPUT_SAMPLES`` samples over ``t_end``: the continuation's fastest pole
    asked for 4e6 samples of every state on a beam at 40 modes (gigabytes), while the
    figures do not depend on the grid from 200 000 samples on (events, impulse and the
    first peak are exact; rod-cantilever at 10 modes: the same four figures at 200 000
    and at the automatic 510 000 samples; at 20 000 the peak came out 1.6 % lower: the
    ringing's crest falls between samples)."""
    method = "laplace" if case.contact.is_linear else "modal"

    def solve(m1, m2):
        b1, b2 = Body(m1, velocity=case.velocity1), Body(m2, velocity=case.velocity2)
        if method == "laplace" and isinstance(case.contact, Rigid):
            _check_search_steps(b1, b2, case.t_end)
        step = case.dt_exact if method == "modal" else dt
        if step is None:
            step = max(choose_dt((b1, b2), case.contact, t_end=case.t_end, method=method),
                       case.t_end / _MAX_OUTPUT_SAMPLES)
        return solve_impact(b1, b2, contact=case.contact, t_end=case.t_end, dt=step,
                            method=method, progress=False)     # the benchmark's own bar
    return solve


#: most event-search steps (at the finest level) an exact solve may need over ``t_end``
#: (the continued 40-mode beam under a rod: 1.2e6)
_MAX_SEARCH_STEPS = 2e7


def _check_search_steps(b1, b2, t_end):
    """Refuse (``ValueError``) a rigid contact whose stuck phase (or free flight) has a
    lightly damped eigenvalue so fast that the exact solver's event search would need
    more than :data:`_MAX_SEARCH_STEPS` steps of ``pi / (8 |lambda|)`` over ``t_end``: such
    a solve runs for hours. An eigenvalue that decays within a few of its own periods
    (damping ratio :data:`_TRANSIENT_DAMPING` or more: the stuck phase's real eigenvalue
    ``-h(0+)/D`` of a continued beam that keeps a static flexibility ``D``, ``-7e6``
    rad/s) does not count: the search takes its transient apart
    (:func:`impactpred.engine.search.first_event`). The stuck phase is built as
    :func:`impactpred.solvers.laplace.solve_laplace` builds it (``A + Bf Kf``)."""
    from .solvers.laplace import CoupledSystem, _relative_degree

    sysm = CoupledSystem((b1, b2))
    if not sysm.n:
        return
    rho, coef = _relative_degree(sysm)
    row = sysm.Cg / coef
    for _ in range(rho):
        row = row @ sysm.A
    stuck = sysm.A - np.outer(sysm.Bf, row)
    eigs = [np.linalg.eigvals(stuck)]
    eigs += [np.concatenate([m.poles, m.real_poles]) for m in sysm.models]  # free flight
    lam = np.concatenate(eigs)
    lasting = -lam.real < _TRANSIENT_DAMPING * np.abs(lam)
    rate = float(np.max(np.abs(lam[lasting]), initial=0.0))
    steps = t_end * 8.0 * rate / math.pi
    if steps > _MAX_SEARCH_STEPS:
        raise ValueError(f"the contact's fastest lightly damped eigenvalue, {rate:.3g} "
                         f"rad/s, needs {steps:.2g} event-search steps over {t_end:g} s "
                         f"(the exact solver's limit here: {_MAX_SEARCH_STEPS:.0e})")


#: eigenvalues of at least this damping ratio are transients the event search takes apart
_TRANSIENT_DAMPING = 0.05


#: solver failures recorded in the table's ``failure`` column instead of raised
_FAILURES = (ValueError, MemoryError, np.linalg.LinAlgError, FloatingPointError)


def _is_measured(body):
    return isinstance(body, (Rod, CantileverBeam))


def body_seed(body, n_modes, noise, run=0) -> int:
    """The hammer test's seed of ``body`` at ``n_modes`` and ``noise`` in run ``run`` (0:
    the benchmark's; the coverage study's runs 1, 2, ...).

    Parameters
    ----------
    body : object
        An exact model of the benchmark.
    n_modes : int
        Modes in the band.
    noise : float
        Noise level (a share, 0.01 for 1 %).
    run : int
        The run (0: the benchmark's).

    Returns
    -------
    int
        The seed.
    """
    return sum(map(ord, repr(body))) * 1000 + n_modes * 10 + int(100 * noise) + 7919 * run


def run_case(case, n_modes, noise, *, reference, cache=None, uncertainty=True, n_draws=4,
             measurement=Measurement(), run=0, level=0.9) -> tuple[dict, object]:
    """One case at one band and noise: a table row and the predicted ``ImpactResult``.

    Parameters
    ----------
    case, n_modes, noise
        The case, the elastic modes the band covers and the hammer-test noise level.
    reference : Reference
        From :func:`exact_reference`.
    cache : dict, optional
        Identifications by ``(repr(body), n_modes, noise, run)`` (their continued models
        by ``("model", ...)`` of the same), the damped truth's figures by ``("damped
        truth", case.key, n_modes)`` and the cut-band re-identifications under
        ``"refits"`` (see :func:`~impactpred.uncertainty.uncertainty_band`), shared across
        cases.
    uncertainty, n_draws, measurement
        Compute the uncertainty band (with ``n_draws`` parameter draws); the measurement.
    run : int
        The hammer tests' seeds (:func:`body_seed`): 0 for the benchmark.
    level : float
        The band's stated coverage (all four figures together).

    Returns
    -------
    (dict, ImpactResult or None)
        The row (see :func:`run_benchmark`); None for a failed prediction (``failure``).
    """
    cache = {} if cache is None else cache
    seconds = {"hammer": 0.0, "frf": 0.0, "identify": 0.0}
    fits, models, truths, tops, lines, frf_noises = [], [], [], [], [], []
    for _i, body in enumerate((case.body1, case.body2)):
        if not _is_measured(body):
            fits.append(None)
            models.append(body)
            truths.append(body)
            continue
        key = (repr(body), n_modes, noise, run)
        if key not in cache:
            cache[key] = measure_body(body, n_modes, noise, seed=body_seed(body, n_modes, noise,
                                                                           run),
                                      measurement=measurement)
            for k, v in cache[key].seconds.items():
                seconds[k] += v
        ident = cache[key]
        fits.append(ident.fit)
        truths.append(ident.truth)
        tops.append(ident.band_top_hz)
        lines.append(ident.n_lines)
        frf_noises.append(ident.frf_noise)
        t0 = time.perf_counter()
        if ("model",) + key not in cache:       # one continued model per identification
            cache[("model",) + key] = identified_model(ident.fit)
        models.append(cache[("model",) + key])
        seconds["continue"] = seconds.get("continue", 0.0) + time.perf_counter() - t0
    solve = _solver(case)
    t0 = time.perf_counter()
    row = {"case": case.key, "family": case.family, "n_modes": n_modes, "noise": noise,
           "failure": ""}
    try:
        result = solve(*models)
    except _FAILURES as exc:            # reported, never hidden: the row keeps NaN errors
        row["failure"] = f"predict: {type(exc).__name__}: {str(exc)[:80]}"
        return row, None
    seconds["predict"] = time.perf_counter() - t0
    resolution = band_resolution(fits)
    figs = impact_figures(result, resolution=resolution)
    # the damped truth's own answer: its first n modes (+ residual), continued, solved
    # (the same at every noise level: once per case and band)
    t0 = time.perf_counter()
    truth_key = ("damped truth", case.key, n_modes)
    if truth_key not in cache:
        damped = []
        for f, tr in zip(fits, truths):
            if f is None:
                damped.append(tr)
                continue
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                damped.append(continue_above_band(
                    tr.truncate(n_modes, residual=True), f.report_["band_hz"][1],
                    extend=tail_extent(f.report_["n_modes"])))
        try:
            cache[truth_key] = (impact_figures(solve(*damped), resolution=resolution), "")
        except _FAILURES as exc:
            cache[truth_key] = ({k: math.nan for k in FIGURES},
                                f"damped truth: {type(exc).__name__}: {str(exc)[:80]}")
    figs_truth, failure = cache[truth_key]
    row["failure"] = row["failure"] or failure
    seconds["truth"] = time.perf_counter() - t0
    band = None
    if uncertainty:
        t0 = time.perf_counter()
        try:
            with warnings.catch_warnings():      # recorded in the row instead
                warnings.filterwarnings("ignore", message="the outcome changes in kind")
                band = uncertainty_band(models, fits, solve, n_draws=n_draws,
                                        nominal=result, level=level,
                                        refits=cache.setdefault("refits", {}),
                                        contact=case.contact)
            row["band_outcome_changes"] = len(band.outcome_changes)
            row["band_outcome_undefined"] = sum("defined" in c for c in band.outcome_changes)
        except _FAILURES as exc:
            row["failure"] = f"band: {type(exc).__name__}: {str(exc)[:80]}"
        seconds["band"] = time.perf_counter() - t0
    exact = reference.figures
    undefined = [k for k in FIGURES if figs[k] is None]
    if undefined:        # e.g. no restitution: still in contact at t_end (a miss, recorded)
        row["failure"] = row["failure"] or f"predict: no {', '.join(undefined)} by t_end"
    for k in FIGURES:
        row[f"{_SHORT[k]}_err_%"] = (math.nan if figs[k] is None
                                     else 100.0 * (figs[k] - exact[k]) / exact[k])
    for k in FIGURES:
        row[f"{_SHORT[k]}_truth_err_%"] = (math.nan if figs_truth[k] is None
                                           else 100.0 * (figs_truth[k] - exact[k]) / exact[k])
    if undefined:
        return row, result
    row["force_err_%"] = 100.0 * _force_error(result, reference)
    row["e_pred"] = figs["restitution"]
    row["e_exact"] = exact["restitution"]
    row["e_above_1"] = bool(figs["restitution"] > 1.0 + 1e-9)
    row["contacts"] = f"{figs['n_contacts']}/{figs['n_contacts_raw']}"
    for k in FIGURES:
        row[f"band_{_SHORT[k]}"] = (None if band is None else
                                   f"{band.low[k]:.5g}..{band.high[k]:.5g}")
        row[f"in_band_{_SHORT[k]}"] = None if band is None else bool(band.contains(k, exact[k]))
        # the band as built before #19 (the variants' range, widened to nominal -+
        # (truncation + tail)), for the widths' comparison; it had no pole draws
        if band is not None:
            values = [band.nominal[k], band.nominal[k] - band.truncation[k] - band.tail[k],
                      band.nominal[k] + band.truncation[k] + band.tail[k]]
            values += [f[k] for label, f in band.variants
                       if f[k] is not None and not label.startswith("pole draw")]
            row[f"band_prev_lo_{_SHORT[k]}_%"] = 100.0 * (min(values) - exact[k]) / exact[k]
            row[f"band_prev_hi_{_SHORT[k]}_%"] = 100.0 * (max(values) - exact[k]) / exact[k]
        # the band's parts in % of the exact value: half-width and its components
        for part, value in (("lo", None if band is None else band.low[k]),
                            ("hi", None if band is None else band.high[k]),
                            ("sigma", None if band is None else band.spread[k]),
                            ("sigma_pole", None if band is None else band.pole_spread[k]),
                            ("trunc", None if band is None else band.truncation[k]),
                            ("tail", None if band is None else band.tail[k]),
                            ("front", None if band is None else band.front[k])):
            row[f"band_{part}_{_SHORT[k]}_%"] = (
                math.nan if value is None else 100.0 * (
                    value - exact[k] if part in ("lo", "hi") else value) / exact[k])
    row["band_hz"] = "/".join(f"{t:.4g}" for t in tops)
    row["lines"] = "/".join(str(n) for n in lines)
    row["frf_noise_%"] = "/".join(f"{100 * n:.2g}" for n in frf_noises)
    row["clipped_poles"] = sum(f.report_["window_clipped"] for f in fits if f is not None)
    row["n_ident_modes"] = "/".join(str(f.report_["n_modes"]) for f in fits if f is not None)
    for k in ("hammer", "frf", "identify", "continue", "predict", "truth", "band"):
        row[f"t_{k}_s"] = seconds.get(k, 0.0)
    row["t_exact_s"] = reference.seconds
    return row, result


#: the cut bands of the band's re-identifications (``uncertainty_band``'s default)
_FRACTIONS = (0.8,)


def _identify_task(body, n, noise, run, measurement, fractions):
    """Stage one: ``body`` measured and identified at band ``n`` and ``noise`` (seed of run
    ``run``), and re-identified on each of ``fractions`` of its band:
    ``(Identified, {fraction: ModalFit}, seconds)``. Each body is identified once however
    many cases use it (a fixed rod: four, the unit free rod: five)."""
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ident = measure_body(body, n, noise, seed=body_seed(body, n, noise, run),
                             measurement=measurement)
        refits = {f: refit_on_cut_band(ident.fit, f) for f in fractions}
    return ident, refits, time.perf_counter() - t0


def _reference_task(case):
    """Stage one: the exact reference of ``case`` (once per case, not per band)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return exact_reference(case)


def _runs_at(case, n_modes):
    """Whether ``case`` is predicted at a band of ``n_modes`` modes (``Case.max_modes``)."""
    return case.max_modes is None or n_modes <= case.max_modes


def _first_stage_task(kind, *args):
    """A stage-one task: ``("reference", case)`` or ``("identify", body, n, noise, run,
    measurement, fractions)``."""
    return _reference_task(*args) if kind == "reference" else _identify_task(*args)


def _run_task(cases, n, noises, band, measurement, progress, start, level, refs=None,
              idents=None):
    """One band ``n`` of some cases at every noise: ``(rows, {(key, noise): (t, force)})``
    (a process of its own under ``workers > 1``; identifications shared inside).

    ``refs``: exact references by case key (else computed here); ``idents``: stage one's
    ``{(repr(body), n, noise, run): (Identified, {fraction: refit}, seconds)}`` (else each
    body is identified here, once per task)."""
    rows, curves, cache = [], {}, {}
    for key, (ident, refits, _) in (idents or {}).items():
        cache[key] = ident
        for fraction, refit in refits.items():
            cache.setdefault("refits", {})[(id(ident.fit), fraction)] = (ident.fit, refit)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        for case in cases:
            ref = exact_reference(case) if refs is None else refs[case.key]
            for noise in noises:
                row, res = run_case(case, n, noise, reference=ref, cache=cache,
                                    uncertainty=band, measurement=measurement, level=level)
                rows.append(row)
                if res is not None:
                    curves[(case.key, noise)] = (np.asarray(res.t), np.asarray(res.force))
    return rows, curves


def _progress_line(row, start):
    """The line printed for a finished row (case, band, noise: errors, band)."""
    head = (f"[{time.perf_counter() - start:6.1f} s] {row['case']:<26} {row['n_modes']:>2} "
            f"modes {100 * row['noise']:g} % noise: ")
    if row["failure"]:
        return head + f"FAILED {row['failure']}"
    return (head + f"e {row['e_err_%']:+.2f} %, J {row['impulse_err_%']:+.2f} %, "
            f"D {row['duration_err_%']:+.2f} %, P {row['peak_err_%']:+.2f} %"
            + ("" if row["in_band_e"] is None else ", band holds D/P/J/e "
               + "/".join("y" if row[f"in_band_{_SHORT[k]}"] else "n" for k in FIGURES)))


def run_benchmark(*, cases=None, bands=(10, 20, 40), noises=(0.01, 0.05), quick=False,
                  out=None, progress=False, band_modes=None, workers=2, level=0.9,
                  measurement=Measurement(), executor=None) -> pd.DataFrame:
    """Run the benchmark; write ``synthetic_benchmark.csv``, ``.md`` and figures to ``out``.

    Parameters
    ----------
    cases : sequence of str or Case, optional
        Case keys (see :func:`benchmark_cases`) or cases; default all.
    bands : sequence of int
        Elastic modes the measured band covers (default 10, 20 and 40).
    noises : sequence of float
        Hammer-test noise levels (std of the white noise over the RMS, or the max, of each
        record: ``measurement.noise_reference``).
    quick : bool
        Only 10 modes, 1 % noise, the mass-rod M/m=1 and rod-rod L2/L1=1 cases (the
        ``cases`` argument still wins when given).
    out : str or Path, optional
        Output directory (created); nothing is written without it.
    progress : bool
        Print one line per case and configuration (stdout) as its task finishes, under a
        tqdm bar of the tasks (stderr). Default False, as at every entry point of the
        library (``impactpred benchmark`` turns it on).
    band_modes : sequence of int, optional
        The bands (mode counts) whose rows get an uncertainty band; default every band,
        ``()`` for none.
    workers : int
        Processes; 1 runs in this process. Stage one identifies every measured body at
        every band and noise once (with its cut-band re-identification) and computes each
        case's exact reference once; stage two runs one case at one band (all noises) per
        task. The numbers do not depend on it (every hammer test has its own seed).
    executor : None, concurrent.futures.Executor or dask.distributed.Client
        Where the tasks run instead (:func:`impactpred.parallel.resolve_executor`; a
        caller's executor or client is left running); ``None``: ``workers`` decides.
    level : float
        The uncertainty band's stated coverage (all four figures together).
    measurement : Measurement
        How the continua are measured.

    Returns
    -------
    pandas.DataFrame
        One row per (case, band, noise): errors in % of the exact value (``*_err_%``), the
        damped truth's own errors (``*_truth_err_%``), ``force_err_%``, the band (whether
        it contains each exact value; its ends, ``sigma``, truncation and tail estimates
        in % of the exact value), contact counts and the time of each stage (s).
        ``attrs["targets"]`` holds :func:`check_targets`, ``attrs["seconds"]`` the total.
    """
    start = time.perf_counter()
    every = {c.key: c for c in benchmark_cases()}
    if quick:
        bands, noises = (10,), (0.01,)
        if cases is None:
            cases = ("mass-rod M/m=1", "rod-rod L2/L1=1")
    chosen = list(every.values()) if cases is None else [
        c if isinstance(c, Case) else every[c] for c in cases]
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ValueError(f"workers must be an integer >= 1, got {workers!r}")
    band_modes = tuple(bands) if band_modes is None else tuple(band_modes)
    check_executor(executor, counts=False)
    # stage one: each case's exact reference and each measured body's identification at
    # each band and noise (with its cut-band re-identification where a band is wanted),
    # once each, the longest first (the widest band, the beams: their records are longest)
    first = {("reference", c.key): ("reference", c) for c in chosen}
    for n in sorted(bands, reverse=True):
        for body in sorted({repr(b): b for c in chosen if _runs_at(c, n)
                            for b in (c.body1, c.body2) if _is_measured(b)}.values(),
                           key=lambda b: not isinstance(b, CantileverBeam)):
            for noise in noises:
                first[(repr(body), n, noise, 0)] = (
                    "identify", body, n, noise, 0, measurement,
                    _FRACTIONS if n in band_modes else ())
    # stage two: one task per case and band (every noise), the widest band and the costliest
    # solves (a rod on a beam, two rods) first
    rank = {"rod-beam": 0, "rod-rod": 1, "ball-beam": 2, "mass-rod": 3}
    tasks = [([c], n) for n in sorted(bands, reverse=True)
             for c in sorted(chosen, key=lambda c: rank.get(c.family, 4)) if _runs_at(c, n)]
    outputs = [None] * len(tasks)
    with progress_bar(len(first) + len(tasks), enabled=progress, desc="benchmark",
                      unit="task") as bar, \
            resolve_executor(executor, default=1 if len(tasks) == 1 else workers) as pool:
        done = dict(zip(first, pool.map(_first_stage_task, list(first.values()),
                                        progress=bar)))
        refs = {key[1]: v for key, v in done.items() if key[0] == "reference"}
        args = [(chunk, n, tuple(noises), n in band_modes, measurement, False, start, level,
                 {c.key: refs[c.key] for c in chunk},
                 {k: done[k] for c in chunk for b in (c.body1, c.body2) if _is_measured(b)
                  for k in [(repr(b), n, noise, 0) for noise in noises]})
                for chunk, n in tasks]
        with closing(pool.as_completed(_run_task, args)) as finished:
            for index, future in finished:
                outputs[index] = future.result()
                for row in outputs[index][0] if progress else ():
                    bar.write(_progress_line(row, start), file=sys.stdout)
                bar.update(1)
    order = {c.key: i for i, c in enumerate(chosen)}
    rows = [r for rs, _ in outputs for r in rs]
    rows += [{"case": c.key, "family": c.family, "n_modes": n, "noise": noise,
              "failure": f"not run: the case's widest band is {c.max_modes} modes"}
             for n in bands for c in chosen if not _runs_at(c, n) for noise in noises]
    rows.sort(key=lambda r: (order[r["case"]], r["n_modes"], r["noise"]))
    table = pd.DataFrame(rows)
    targets = check_targets(table)
    table.attrs["targets"] = targets
    table.attrs["seconds"] = time.perf_counter() - start
    table.attrs["identify_seconds"] = sum(v[2] for k, v in done.items() if k[0] != "reference")
    if out is not None:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        curves = {}
        for (_chunk, n), (_, c) in zip(tasks, outputs):
            for (key, noise), curve in c.items():
                curves.setdefault(key, {})[(n, noise)] = curve
        for case in chosen:
            got = {k: v for k, v in curves.get(case.key, {}).items() if k[1] == min(noises)}
            _plot(out, case, refs[case.key], got)
        table.to_csv(out / "synthetic_benchmark.csv", index=False)
        (out / "synthetic_benchmark.md").write_text(
            markdown_table(table) + "\n\n" + error_table(table) + "\n\n" + _markdown(targets)
            + "\n" + f"\nTotal time {table.attrs['seconds']:.0f} s.\n")
    return table
