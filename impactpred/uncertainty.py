"""The uncertainty band of an impact predicted from identified models.

:func:`uncertainty_band` gives each of duration, peak, impulse and restitution an interval
meant to hold the four exact figures together with a stated probability (``level``, 0.9
by default): ``nominal -+ (sqrt((z k sigma)**2 + (a truncation_left)**2) + b tail)``
(:func:`band_half_width`), where ``sigma`` is the figure's rms change over draws of the
fits' parameters from their reported standard deviations (``hypot`` of the change over
draws of the residues, rigid mass and residual flexibility, and over draws of the poles:
natural frequencies and damping ratios), ``truncation`` the error a re-identification on
80 % of each band implies at the full band (:func:`truncation_error`: a figure converging
like ``1/band``, four times its change) and ``truncation_left`` what of it the
identification's noise does not explain,
``tail`` the change when the continuation runs half as far, ``z`` the normal quantile of
the level shared by the four figures (Bonferroni) and ``k``, ``a``, ``b``
(:data:`SPREAD_FACTOR`, :data:`TRUNCATION_FACTOR`, :data:`TAIL_FACTOR`) the parts' factors
calibrated by the coverage study ``benchmarks/band_coverage.py`` on seeds other than those
it reports. Under a rigid contact the peak's interval reaches further down by the overshoot
a band-limited model makes where the force jumps (a wave front arriving at the contact;
:func:`front_allowance`): the one error of a known sign.
The band spans the identification's scatter, the band's truncation and the tail's extent;
a bias of the fit shows only as far as the cut band or the draws move with it.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from .contact import ContactLaw, Rigid
from ._cut_band import (check_band_bodies, check_refittable, refit_on_cut_band,
                        truncation_error)
from ._draws import perturb_poles, perturb_residues
from ._wave_front import FRONT_OVERSHOOT, front_allowance, front_jump
from .parallel import check_executor, progress_bar, resolve_executor
from .truncation import (FIGURES, NoComplianceAbove, band_resolution, identified_model,
                         impact_figures, tail_extent)

__all__ = ["UncertaintyBand", "band_half_width", "check_band_bodies", "FRONT_OVERSHOOT",
           "front_allowance", "front_jump", "outcome_change", "perturb_poles",
           "perturb_residues", "refit_on_cut_band", "truncation_error", "uncertainty_band"]


@dataclass(frozen=True)
class UncertaintyBand:
    """Spread of the impact figures over re-identified and perturbed models.

    Attributes
    ----------
    nominal : dict
        Figures of the nominal prediction (see :func:`impact_figures`).
    low, high : dict
        Bounds of each figure in :data:`FIGURES`: ``nominal -+`` :func:`band_half_width`
        of its ``spread``, ``truncation`` and ``tail`` (see :func:`uncertainty_band`).
    variants : tuple of (str, dict)
        Each variant's label (``"body2 band 60%"``, ``"draw 1"``) and figures.
    truncation : dict or None
        The truncation error left at the full band, per figure, estimated from the cut
        bands (:func:`truncation_error`, the largest over the cut bands; 0 where no cut
        band gave one), before the identification's noise is taken out of it
        (:func:`band_half_width`); None when the band was built without it.
    tail : dict or None
        The error of the continuation's finite extent, per figure: the change when its
        synthesized modes run half as far (taken as the error left, as for an error
        ``~ 1/extend``: a heuristic estimate that errs wide); 0 without continuation.
    spread : dict or None
        The rms change of each figure over the draws of the residues, rigid mass and
        residual flexibility (:func:`perturb_residues`; 0 without draws).
    level : float or None
        The stated probability that the four intervals hold the four exact figures.
    pole_spread : dict or None
        The rms change of each figure over the draws of the poles (:func:`perturb_poles`;
        0 without draws); the band's ``sigma`` is ``hypot(spread, pole_spread)``.
    front : dict or None
        How much further down than ``nominal -`` the half-width the interval reaches, per
        figure (its units): the peak force's wave-front overshoot under a rigid contact
        (:func:`front_allowance`), 0 for the other figures; None when the band was built
        without it.
    outcome_changes : tuple of str
        The variants whose outcome differs in kind from their reference run's (another
        number of contacts, or a figure one defines and the other does not, e.g. no
        restitution when the bodies are still in contact at ``t_end``), each as
        ``"label: what"``; empty when every variant agrees. A figure defined in one run
        and not in the other is left out of the spread and warned about; another number
        of contacts (a brief re-contact that comes and goes) is in the spread of the
        figures it moves, and listed here and in :meth:`table`.
    """

    nominal: dict
    low: dict
    high: dict
    variants: tuple
    truncation: dict | None = None
    tail: dict | None = None
    spread: dict | None = None
    level: float | None = None
    front: dict | None = None
    pole_spread: dict | None = None
    outcome_changes: tuple = ()

    def contains(self, name: str, value: float, *, rel: float = 0.0) -> bool:
        """Whether ``value`` lies in ``[low, high]`` of figure ``name`` (widened by ``rel``).

        Parameters
        ----------
        name : str
            A figure: ``contact_duration``, ``peak_force``, ``impulse`` or ``restitution``.
        value : float
            The value to test (the figure's unit).
        rel : float, keyword-only
            Widen the interval by this share of the nominal.

        Returns
        -------
        bool
        """
        lo, hi = self.low[name], self.high[name]
        return lo * (1 - rel) <= value <= hi * (1 + rel) if lo >= 0 else lo <= value <= hi

    def table(self) -> str:
        """A short text table: figure, nominal, low, high (``-`` for a figure the run does
        not define, e.g. the restitution of bodies still in contact at ``t_end``).

        Returns
        -------
        str
        """
        def cell(value):
            return f"{'-':>14}" if value is None else f"{value:>14.6g}"

        lines = [f"{'figure':<18}{'nominal':>14}{'low':>14}{'high':>14}"]
        for name in FIGURES:
            lines.append(f"{name:<18}{cell(self.nominal[name])}{cell(self.low[name])}"
                         f"{cell(self.high[name])}")
        if self.outcome_changes:
            lines.append(_changes_text(self.outcome_changes, len(self.variants)))
        return "\n".join(lines)


def _changes_text(changes, n_variants: int, shown: int = 4) -> str:
    """The line "the outcome changes in kind in k of n variants: ..." (the first
    ``shown`` of ``changes``)."""
    return (f"the outcome changes in kind in {len(changes)} of {n_variants} variants: "
            + "; ".join(changes[:shown]) + ("; ..." if len(changes) > shown else ""))


def _defined_in_one(reference: dict, figures: dict) -> list:
    """The figures of :data:`FIGURES` defined in one run and not the other."""
    return [k for k in FIGURES if (figures[k] is None) != (reference[k] is None)]


def outcome_change(reference: dict, figures: dict) -> str | None:
    """How a variant's outcome differs in kind from its reference's (figures of
    :func:`impact_figures`, computed alike: same resolution, same continuation): another
    number of contacts, or a figure of :data:`FIGURES` that one defines and the other
    does not; None when they agree.

    Parameters
    ----------
    reference, figures : dict
        The reference run's figures and the variant's.

    Returns
    -------
    str or None
    """
    what = []
    if figures["n_contacts"] != reference["n_contacts"]:
        what.append(f"{figures['n_contacts']} contacts instead of "
                    f"{reference['n_contacts']}")
    for k in _defined_in_one(reference, figures):
        what.append(f"{k} {'undefined' if figures[k] is None else 'defined'}")
    return ", ".join(what) or None


def _physical_interval(figure: str, low: float, high: float) -> tuple:
    """``(low, high)`` within what ``figure`` can be: a duration, peak force or impulse
    is not negative, a coefficient of restitution lies in [-1, 1] (below 0: the bodies
    parted while the struck point recoiled). A spread wider than the figure (a chattering
    run's peak force, from 4 draws) had given a peak force's interval down to -272 N."""
    if figure == "restitution":
        return max(low, -1.0), min(high, 1.0)
    return max(low, 0.0), high


#: the factors of the band's three parts in :func:`band_half_width`, ``sqrt((z
#: SPREAD_FACTOR sigma)**2 + (TRUNCATION_FACTOR truncation_left)**2) + TAIL_FACTOR tail``,
#: calibrated together by ``benchmarks/band_coverage.py --calibrate 21-28`` (seed runs 21-28,
#: 10 and 20 modes, 1 % and 5 % noise, 320 rows): the narrowest band at 1 % noise, by its
#: largest median half-width ratio to the band before #19, that holds all four figures in
#: 90 % of the rows of every (modes, noise). The coverage reported (runs 1-20) and the
#: history of the factors: benchmarks/README.md. (Until the front allowance, the peak's
#: tail factor was twice the others': it stood in for the wave front's overshoot.)
SPREAD_FACTOR = 1.35
#: see :data:`SPREAD_FACTOR`
TRUNCATION_FACTOR = 1.75
#: see :data:`SPREAD_FACTOR`
TAIL_FACTOR = 1.5


def band_half_width(spread: float, truncation: float, tail: float, *, figure: str,
                    pole_spread: float = 0.0, fraction: float = 0.8,
                    level: float = 0.9) -> float:
    """The half-width of a figure's interval from the band's three parts.

    ``sqrt((z k sigma)**2 + (a left)**2) + b tail`` with ``sigma = hypot(spread,
    pole_spread)`` and ``left = max(truncation - sigma sqrt(f / (1 - f)), 0)``: the cut
    band's change holds the re-identification's own random error (about ``sigma
    sqrt(1/f - 1)`` for a fit on the share ``f`` of the lines, nested in the full one),
    which :func:`truncation_error` multiplies by ``f / (1 - f)``; only what exceeds it is
    taken as truncation error, and what is left is combined with the spread as an
    independent error (root sum of squares). The tail's
    estimate is added in full. ``z``: the normal quantile of ``1 - (1 - level) / 8``
    (four figures, two-sided, Bonferroni); ``k, a, b``: :data:`SPREAD_FACTOR`,
    :data:`TRUNCATION_FACTOR`, :data:`TAIL_FACTOR`. (The peak's further reach down at a
    wave front is :func:`front_allowance`, added by :func:`uncertainty_band`.)

    Parameters
    ----------
    spread, truncation, tail : float
        The figure's parts (its units): the residue draws' rms change, the truncation
        estimate of :func:`truncation_error` from the cut band ``fraction``, the tail's
        change.
    figure : str, keyword-only
        The figure (one of :data:`~impactpred.truncation.FIGURES`).
    pole_spread : float, keyword-only
        The pole draws' rms change (its units; 0: none).
    fraction : float, keyword-only
        The cut band's share of the band, in (0, 1).
    level : float, keyword-only
        The stated probability of the four intervals together, in (0, 1).

    Returns
    -------
    float
        The half-width (the figure's units).
    """
    from scipy.stats import norm

    if figure not in FIGURES:
        raise ValueError(f"figure must be one of {FIGURES}, got {figure!r}")
    if not (isinstance(fraction, (int, float)) and 0.0 < fraction < 1.0):
        raise ValueError(f"fraction must lie in (0, 1), got {fraction!r}")
    if not (isinstance(level, (int, float)) and 0.0 < level < 1.0):
        raise ValueError(f"level must lie in (0, 1), got {level!r}")
    z = float(norm.ppf(1.0 - (1.0 - level) / 8.0))
    sigma = math.hypot(spread, pole_spread)
    left = max(truncation - sigma * math.sqrt(fraction / (1.0 - fraction)), 0.0)
    return math.hypot(z * SPREAD_FACTOR * sigma, TRUNCATION_FACTOR * left) + TAIL_FACTOR * tail


#: the two kinds of parameter draw: variant label, what is drawn (for messages), the draw
#: (each kind has its own generator: stream 0 is ``default_rng(seed)``, stream n
#: ``default_rng([seed, n])``, so that adding a kind leaves the others' draws as they were)
_DRAW_KINDS = (("draw", "residue", perturb_residues), ("pole draw", "pole", perturb_poles))

#: a variant's solve that raises one of these has no figures (a degenerate re-identification
#: or draw; the exact solver's undecidable grazing contact, RuntimeError, which a pole draw
#: of the rod-cantilever at 20 modes met at t = 1e-14 s): it is left out, and a draw's is said
_SOLVE_FAILURES = (ValueError, MemoryError, np.linalg.LinAlgError, RuntimeError)

#: the variants are solved with the tail to half as far when the widest band holds more
#: than this many modes (the solve's cost grows like the square of the modes the tail
#: synthesizes: a free rod at 40 modes 13.6 s with the tail to 16x, 1.2 s to 8x); their
#: change is measured against the nominal models solved the same way
CHEAP_VARIANTS_ABOVE = 12


def _bands_modes(fits) -> int:
    """The most physical modes inside any fit's band (0 without a fit)."""
    counts = [int(f.report_.get("n_modes", 0)) for f in fits if f is not None]
    return max(counts, default=0)


def uncertainty_band(models, fits, solve, *, fractions=(0.8,), n_draws: int = 4,
                     seed: int = 0, continuation: bool = True, n_top: int = 3,
                     extend: float | None = None, nominal=None, level: float = 0.9,
                     cheap_variants: bool | None = None,
                     refits: dict | None = None, executor=None,
                     contact: ContactLaw = Rigid(),
                     tail_variant: bool = True, progress=False) -> UncertaintyBand:
    """An interval for each of duration, peak, impulse and restitution, meant to hold all
    four exact figures together with probability ``level``.

    Each figure's interval is ``nominal -+`` :func:`band_half_width`, ``sqrt((z k
    sigma)**2 + (a truncation_left)**2) + b tail`` (``k, a, b``: :data:`SPREAD_FACTOR`,
    :data:`TRUNCATION_FACTOR`, :data:`TAIL_FACTOR`):

    * ``sigma``: the identification's random error, ``hypot`` of the root-mean-square
      change of the figure over ``n_draws`` draws of every identified body's residues,
      rigid mass and residual flexibility (:func:`perturb_residues`; ``spread``) and over
      ``n_draws`` draws of its poles (:func:`perturb_poles`; ``pole_spread``), each from
      the fit's reported standard deviations;
    * ``truncation``: the error the re-identifications on ``fractions`` of each band imply
      at the full band (:func:`truncation_error`); ``truncation_left``: what of it exceeds
      the re-identification's own noise, ``sigma sqrt(f / (1 - f))`` (the largest over
      the fractions ``f``);
    * ``tail``: the change when the continuation's synthesized modes run half as far;
    * ``z``: the normal quantile of ``1 - (1 - level) / 8`` (two-sided, the four figures
      together by Bonferroni's bound: 2.24 for 0.9).

    The tail's estimate is added in full (a bias); the truncation's, once the noise is out
    of it, in quadrature with the spread. Under a rigid contact the peak's interval also
    reaches :func:`front_allowance` further down (the overshoot at a wave front, an error
    of known sign). The level is stated, not guaranteed: it is verified by the coverage
    study (``benchmarks/band_coverage.py``), which calibrated the factors.

    Parameters
    ----------
    models : sequence of 2 models
        The nominal model of each body (as used for the nominal prediction).
    fits : sequence of 2 (ModalFit or None)
        The fit of each body identified from an FRF; only these are varied (a
        :class:`modalid.SavedFit` has no data to re-identify: ValueError).
    solve : callable
        ``solve(model1, model2) -> ImpactResult``.
    fractions : sequence of float
        Each identified body is re-identified on its band cut to these fractions of the
        band top (one body at a time, the other nominal) and continued above the cut.
    n_draws : int
        Draws of each kind (residues, poles; fixed ``seed``) of every identified body's
        parameters (0: no ``sigma``).
    continuation, n_top, extend
        How the identified bodies are continued (:func:`identified_model`; ``extend``
        None: :func:`~impactpred.truncation.tail_extent` of each fit's modes, as the
        nominal models).
    nominal : ImpactResult, optional
        The nominal result, if already solved.
    level : float
        The stated probability (0 < level < 1) that the four intervals hold the four
        exact figures together.
    cheap_variants : bool, optional
        Solve the variants (cut bands, draws) with the continuation to half its extent
        and take their changes against the nominal models solved so (the tail's
        estimate, which is that solve). Default: when a band holds more than
        :data:`CHEAP_VARIANTS_ABOVE` modes.
    refits : dict, optional
        A cache of the cut-band re-identifications, by ``(id(fit), fraction)`` (the caller
        keeps the fits alive): one body in several impacts is re-identified once.
    executor : None, concurrent.futures.Executor or dask.distributed.Client
        Where the re-identifications and the variants' solves run
        (:func:`impactpred.parallel.resolve_executor`; ``None``: in this process, one
        after the other; an executor of the caller's is left running). Under processes
        ``solve`` must pickle (a module-level function or a ``functools.partial`` of one;
        a Dask client also ships closures). The band does not depend on it.
    contact : ContactLaw
        The contact law ``solve`` uses (:func:`~impactpred.solve_impact`'s default, rigid).
        Under :class:`~impactpred.contact.Rigid` the force may jump at a wave front, and
        with ``continuation`` the peak's interval reaches :func:`front_allowance` lower;
        a compliant law's force is continuous.
    tail_variant : bool
        Solve the tail's variant (the continuation's synthesized modes half as far);
        False leaves its part at 0 (``predict``'s band check: a solve saved).
    progress : bool or "auto"
        A bar on stderr counting the re-identifications and solves done
        (:func:`impactpred.parallel.progress_bar`; ``"auto"``: once the band has taken
        10 s). Two wide FRFs' band took 18 s in silence after their fits.

    Returns
    -------
    UncertaintyBand
        ``low``/``high`` per figure, ``spread`` and ``pole_spread`` (``sigma``'s parts),
        ``truncation``, ``tail``, ``front``, ``level`` and every variant's figures.
    """
    if extend is not None and not (isinstance(extend, (int, float)) and math.isfinite(extend)
                                   and extend > 0):
        raise ValueError(f"extend must be a positive finite number, got {extend!r}")
    if isinstance(n_draws, bool) or not isinstance(n_draws, (int, np.integer)) or n_draws < 0:
        raise ValueError(f"n_draws must be an integer >= 0, got {n_draws!r}")
    if isinstance(n_top, bool) or not isinstance(n_top, (int, np.integer)) or n_top < 1:
        raise ValueError(f"n_top must be an integer >= 1, got {n_top!r}")
    for fraction in fractions:
        if not (isinstance(fraction, (int, float)) and 0.0 < fraction < 1.0):
            raise ValueError(f"fractions must lie in (0, 1), got {fraction!r}")
    if not (isinstance(level, (int, float)) and 0.0 < level < 1.0):
        raise ValueError(f"level must lie in (0, 1), got {level!r}")
    if not isinstance(contact, ContactLaw):
        raise TypeError(f"contact must be a ContactLaw, got {contact!r}")
    check_executor(executor, counts=False)
    for fit in fits:
        check_refittable(fit)
    if cheap_variants is None:
        cheap_variants = _bands_modes(fits) > CHEAP_VARIANTS_ABOVE
    models = list(models)
    if nominal is None:
        nominal = solve(*models)
    resolution = band_resolution(fits)
    base = impact_figures(nominal, resolution=resolution)
    measured = any(f is not None for f in fits)
    variants = []
    kind_changes = []    # (label, how its outcome differs in kind, figures defined in one only)

    def compare(label, reference_figs, figs):
        kind_changes.append((label, outcome_change(reference_figs, figs),
                             _defined_in_one(reference_figs, figs)))

    def extent(fit):
        return tail_extent(fit.report_.get("n_modes", 0)) if extend is None else extend

    def continued(fit, share=1.0, of=None, **kw):
        """``fit`` (or ``of``, a refit) continued to ``share`` of ``fit``'s extent; as
        identified where it cannot be continued (as ``predict`` did for the nominal
        model: no mode in its band, or no compliance above it)."""
        source = fit if of is None else of
        try:
            return identified_model(source, continuation=continuation, n_top=n_top,
                                    extend=share * extent(fit), **kw)
        except NoComplianceAbove:                 # as identified, its upper terms dropped
            return identified_model(source, continuation=False, **kw)
        except ValueError:
            if not continuation:
                raise
            return identified_model(source, continuation=False, **kw)

    # the variants are not the answer: their warnings (no contact, chatter, ...) would
    # repeat the nominal solve's once per variant. One filter, set here in the calling
    # thread (catch_warnings is not thread-safe: one per task on a thread pool could
    # leave "ignore" behind for good)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        # the re-identifications on the cut bands start first: they run while the tail solves
        pool = resolve_executor(executor, default=1)
        bar = progress_bar(None, enabled=progress, desc="band variants", unit=" solve")

        def submit(fn, *args):          # the bar counts what is done
            job = pool.submit(fn, *args)
            job.add_done_callback(lambda _: bar.update())
            return job
        pending = {}
        for fit in fits:
            for fraction in fractions if fit is not None else ():
                key = (id(fit), fraction)
                if key not in pending and (refits is None or key not in refits):
                    pending[key] = submit(refit_on_cut_band, fit, fraction)
        # the tail's own extent: synthesized modes to half as far; the change, taken as the
        # error left (as for an error ~ 1/extend), is a heuristic that errs wide: a peak's
        # change from 8x to 16x exceeded its change from 16x to 32x by 2x on a rod
        tail = {k: 0.0 for k in FIGURES}
        half = None
        if (tail_variant and continuation and measured
                and all(f is None or extent(f) > 1.0 for f in fits)):
            try:
                half = submit(solve, *[m if f is None else continued(f, 0.5)
                                       for f, m in zip(fits, models)]).result()
            except _SOLVE_FAILURES:
                half = None
            if half is not None:
                figs = impact_figures(half, resolution=resolution)
                reach = "/".join(f"{0.5 * extent(f):.3g}" for f in fits if f is not None)
                variants.append((f"tail to {reach}x the band top", figs))
                compare(variants[-1][0], base, figs)
                tail = truncation_error(base, figs, 0.5)
        # the variants' reference: the nominal models with the variants' extent
        share = 0.5 if (cheap_variants and continuation and half is not None) else 1.0
        reference = half if share < 1.0 else nominal
        cuts, cut_jobs = [], []
        for i, fit in enumerate(fits):
            if fit is None:
                continue
            for fraction in fractions:
                key = (id(fit), fraction)
                if refits is None or key not in refits:
                    refit = pending[key].result()
                    if refits is not None:
                        refits[key] = (fit, refit)
                else:
                    refit = refits[key][1]
                trial = list(models)
                try:
                    trial[i] = continued(fit, share, of=refit)
                except ValueError:
                    continue
                cut_fits = [refit if j == i else f for j, f in enumerate(fits)]
                if share < 1.0:
                    trial = [t if j == i or f is None else continued(f, share)
                             for j, (t, f) in enumerate(zip(trial, fits))]
                cut_jobs.append((i, fraction, cut_fits, submit(solve, *trial)))
        ref_figs = impact_figures(reference, resolution=resolution)
        changes: dict[str, dict] = {kind: {k: [] for k in FIGURES} for kind, _, _ in _DRAW_KINDS}
        draw_jobs = []     # the draws made here, in order (a generator per kind); solves pooled
        if measured:
            for stream, (kind, _, perturb) in enumerate(_DRAW_KINDS):
                rng = np.random.default_rng(seed if seed is None or stream == 0
                                            else [seed, stream])
                for d in range(n_draws):
                    trial = list(models)
                    for i, fit in enumerate(fits):
                        if fit is not None:
                            trial[i] = continued(fit, share, model=perturb(fit, rng))
                    draw_jobs.append((kind, d, submit(solve, *trial)))
        for i, fraction, cut_fits, job in cut_jobs:
            try:
                res = job.result()
            except _SOLVE_FAILURES:
                continue                 # a degenerate re-identification: no figure
            cut_resolution = band_resolution(cut_fits)
            figs = impact_figures(res, resolution=cut_resolution)
            label = f"body{i + 1} band {100 * fraction:.0f}%"
            variants.append((label, figs))
            # compared with the reference at the same resolution (the same merging)
            same = impact_figures(reference, resolution=cut_resolution)
            cuts.append((fraction, figs, same))
            compare(label, same, figs)
        failed: dict[str, list] = {kind: [] for kind, _, _ in _DRAW_KINDS}
        if measured:
            for kind, d, job in draw_jobs:
                try:
                    figs = impact_figures(job.result(), resolution=resolution)
                except _SOLVE_FAILURES as exc:
                    failed[kind].append(f"{type(exc).__name__}: {str(exc)[:120]}")
                    continue
                variants.append((f"{kind} {d + 1}", figs))
                compare(f"{kind} {d + 1}", ref_figs, figs)
                for k in FIGURES:
                    if figs[k] is not None and ref_figs[k] is not None:
                        changes[kind][k].append(figs[k] - ref_figs[k])
        bar.close()
    for kind, what, _ in _DRAW_KINDS:
        if failed[kind]:
            lost = len(failed[kind]) == n_draws
            warnings.warn(f"{len(failed[kind])} of {n_draws} {what} draws could not be solved "
                          f"(first: {failed[kind][0]}); the band's {what} spread comes from "
                          f"the {n_draws - len(failed[kind])} others"
                          + (f": it has no {what} spread part" if lost else ""),
                          RuntimeWarning, stacklevel=2)
    spread, pole_spread = ({k: (math.sqrt(float(np.mean(np.square(v)))) if v else 0.0)
                            for k, v in changes[kind].items()} for kind, _, _ in _DRAW_KINDS)
    trunc = {k: 0.0 for k in FIGURES}
    halves = {k: band_half_width(spread[k], 0.0, tail[k], figure=k, level=level,
                                 pole_spread=pole_spread[k]) for k in FIGURES}
    for fraction, figs, same in cuts:
        for k, r in truncation_error(same, figs, fraction).items():
            trunc[k] = max(trunc[k], r)
            halves[k] = max(halves[k], band_half_width(spread[k], r, tail[k], figure=k,
                                                       pole_spread=pole_spread[k],
                                                       fraction=fraction, level=level))
    front = {k: 0.0 for k in FIGURES}
    if continuation and measured and isinstance(contact, Rigid):
        front["peak_force"] = front_allowance(front_jump(nominal, resolution),
                                              sum(f is not None for f in fits))
    # a figure some variant does not define (still in contact at t_end, no contact) has
    # no spread to measure: its interval is all it can be. Left out of the spread, the
    # rest had made a ball on a beam's restitution [0.25, 0.36] for an exact 0.059
    unmeasured = {k for _, _, undefined in kind_changes for k in undefined}
    low: dict[str, float | None] = {}
    high: dict[str, float | None] = {}
    for k in FIGURES:
        if base[k] is None:
            low[k] = high[k] = None
            continue
        if k in unmeasured:
            low[k], high[k] = _physical_interval(k, -math.inf, math.inf)
            continue
        low[k], high[k] = _physical_interval(k, base[k] - halves[k] - front[k],
                                             base[k] + halves[k])
    changes_of_kind = tuple(f"{label}: {what}" for label, what, _ in kind_changes if what)
    mismatched = [f"{label}: {what}" for label, what, undefined in kind_changes if undefined]
    if mismatched:         # a figure the band's spread cannot hold: said loudly
        whole = ", ".join(f"{k} [{low[k]:.4g}, {high[k]:.4g}]" for k in FIGURES
                          if k in unmeasured and low[k] is not None)
        warnings.warn(_changes_text(mismatched, len(variants), shown=3) + " (a figure "
                      "defined in the variant or its reference only is left out of the "
                      "band's spread"
                      + (f"; its interval is all it can be: {whole})" if whole else ")"),
                      UserWarning, stacklevel=2)
    return UncertaintyBand(nominal=base, low=low, high=high, variants=tuple(variants),
                           truncation=trunc, tail=tail, spread=spread, level=level,
                           front=front, pole_spread=pole_spread,
                           outcome_changes=changes_of_kind)
