"""The synthetic benchmark's cases, exact references and measurements (for
:mod:`impactpred.benchmark`, which documents them and re-exports the public names).

* :func:`benchmark_cases` and :class:`Case`: the ten pairs of bodies and their contacts;
* :func:`exact_reference` and :class:`Reference`: the exact answer of a case (closed forms,
  or the convolution solver on the exact models);
* :func:`measure_body`, :class:`Measurement` and :func:`fit_max_order`: a synthetic hammer
  test of a continuum and its identification.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from data_synth import CantileverBeam, LumpedMass, Rod, lightly_damped
from data_synth.measure import synthetic_hammer_test
from data_synth.reference_impacts import mass_on_fixed_rod, two_free_rods_equal_transit
from modalid import ModalFit
from modalid.hammer import frf_from_hammer

from .api import solve_impact
from .body import Body
from .contact import Hertz, LinearSpring, Rigid
from .truncation import FIGURES, impact_figures

__all__ = ["Case", "Identified", "Measurement", "Reference", "benchmark_cases",
           "exact_reference", "fit_max_order", "gap_crossing_duration", "measure_body"]


# ------------------------------------------------------------------------- cases
@dataclass(frozen=True)
class Case:
    """One benchmark case: two exact bodies, their speeds, the contact and the reference.

    ``reference`` names how the exact answer is computed: ``"mass_on_fixed_rod"``,
    ``"two_free_rods"`` or ``"convolution"`` (then with step ``dt_exact``, and with
    ``richardson``, extrapolated from ``dt_exact`` and ``dt_exact / 2``).

    Parameters
    ----------
    key : str
        The case's label.
    family : str
        Its family (``"mass-rod"``, ``"rod-rod"``, ...).
    description : str
        One line saying what it is.
    body1, body2 : object
        The exact models (``data_synth``) of the two bodies.
    velocity1, velocity2 : float
        Their velocities before the impact (m/s).
    t_end : float
        End of the simulation (s).
    reference : str
        How the exact answer is computed (above).
    dt_exact : float, optional
        The convolution reference's step (s).
    richardson : bool
        Extrapolate the convolution reference's peak, impulse and restitution to
        ``dt = 0`` from ``dt_exact`` and ``dt_exact / 2`` (first order:
        ``2 f(dt/2) - f(dt)``), where they converge like ``dt`` and the predictions are
        closer than that error (the ball: 0.025-0.045 % per halving at 1e-8 s, three
        halvings checked). Under a contact whose force vanishes with the gap (Hertz, an
        undamped spring) the duration is measured where the gap crosses zero
        (:func:`gap_crossing_duration`) and extrapolated too; otherwise it is the finer
        step's, on its grid.
    contact : ContactLaw
        The contact law (default rigid).
    max_modes : int, optional
        The widest band predicted (None: every band). A wider band's rows are reported
        as not run (``failure``; they count as misses).
    """

    key: str
    family: str
    description: str
    body1: object
    body2: object
    velocity1: float
    velocity2: float
    t_end: float
    reference: str
    dt_exact: float | None = None
    richardson: bool = False
    contact: object = field(default_factory=Rigid)
    max_modes: int | None = None


def _steel_ball(radius):
    return LumpedMass(7850.0 * 4.0 / 3.0 * math.pi * radius**3)


#: steel bar cantilever 0.5 m x 40 mm x 10 mm (E 210 GPa, 7850 kg/m^3): f1 = 33 Hz
_STRIP_MASS = 7850.0 * 0.5 * 40e-3 * 10e-3
_STRIP_T = math.sqrt(_STRIP_MASS / (210e9 * 40e-3 * 10e-3**3 / 12.0 / 0.5**3))


def benchmark_cases() -> list[Case]:
    """The benchmark's cases (units SI; rods of mass 1 kg and transit time 1 s unless said).

    Returns
    -------
    list of Case
    """
    fixed = Rod(1.0, 1.0, support="fixed")
    cases = []
    for ratio in (0.5, 1.0, 2.0, 4.0):
        cases.append(Case(f"mass-rod M/m={ratio:g}", "mass-rod",
                          f"mass M = {ratio:g} m at 1 m/s on the free end of a fixed rod at rest"
                          + (" (paper c)" if ratio == 1.0 else ""),
                          LumpedMass(ratio), fixed, 1.0, 0.0, 4.0 + 4.0 * ratio,
                          "mass_on_fixed_rod"))
    cases.append(Case("rod-rod L2/L1=1", "rod-rod", "equal free rods, +1 and -1 m/s (paper a)",
                      Rod(1.0, 1.0), Rod(1.0, 1.0), 1.0, -1.0, 6.0, "two_free_rods"))
    for lr in (0.75, 0.5):
        cases.append(Case(f"rod-rod L2/L1={lr:g}", "rod-rod",
                          f"free rods of one material and section, L2 = {lr:g} L1, +1 and -1 m/s"
                          + (" (paper b, equal material)" if lr == 0.75 else ""),
                          Rod(1.0, 1.0), Rod(lr, lr), 1.0, -1.0, 6.0, "convolution",
                          dt_exact=1.0 / 2000))
    cases.append(Case("rod-rod T2=0.75T1 equal m", "rod-rod",
                      "free rods of equal mass, T2 = 0.75 T1, +1 and -1 m/s (paper b, stepped)",
                      Rod(1.0, 1.0), Rod(1.0, 0.75), 1.0, -1.0, 6.0, "convolution",
                      dt_exact=1.0 / 2000))
    cases.append(Case("rod-cantilever", "rod-beam",
                      "free rod at 1 m/s on the tip of a cantilever at rest (mass 10 kg, time "
                      "scale 4 s; paper d)", Rod(1.0, 1.0), CantileverBeam(10.0, 4.0), 1.0, 0.0,
                      8.0, "convolution", dt_exact=1.0 / 2000))
    ball = _steel_ball(0.005)
    cases.append(Case("ball-cantilever Hertz", "ball-beam",
                      f"steel ball R = 5 mm ({1e3 * ball.mass:.2f} g) at 1 m/s, Hertz contact, "
                      "on the tip of a steel bar cantilever 500 x 40 x 10 mm at rest",
                      ball, CantileverBeam(_STRIP_MASS, _STRIP_T), 1.0, 0.0, 2e-4,
                      "convolution", dt_exact=1e-8, richardson=True,
                      contact=Hertz.from_materials(radius1=0.005, youngs_modulus1=210e9,
                                                   poisson1=0.3, youngs_modulus2=210e9,
                                                   poisson2=0.3)))
    return cases


# --------------------------------------------------------------------- references
@dataclass(frozen=True)
class Reference:
    """Exact answer of a case: figures (see :data:`FIGURES`), force history, how, seconds.

    Parameters
    ----------
    figures : dict
        The exact figures (see :data:`FIGURES`).
    t : numpy.ndarray
        Times (s).
    force : numpy.ndarray
        The exact contact force (N) at ``t``.
    how : str
        How it was computed.
    seconds : float
        How long that took (s).
    """

    figures: dict
    t: np.ndarray
    force: np.ndarray
    how: str
    seconds: float


def gap_crossing_duration(result) -> float:
    """Duration (s) of the first contact, its ends placed where the gap crosses zero.

    A time-stepping solution's contact intervals start and end on its grid (its force is
    constant over each step), so their duration is a multiple of the step: the ball of
    :func:`benchmark_cases` at ``dt = 5e-9`` s gives 33.870 us, 0.0077 % under the limit
    ``dt -> 0`` (33.8726 us), more than its uncertainty band's half-width at 40 modes. Under
    a contact whose force vanishes with the gap (Hertz, an undamped spring) the gap is
    negative while the bodies press, and the samples on either side of its closing and of
    its opening bracket the contact's ends: linear interpolation of the gap puts each end
    within ``O(dt^2)`` of the discrete solution's crossing, which converges to the exact
    one like ``dt`` (then Richardson's extrapolation applies, as to the other figures). A
    dashpot ends the force before the gap opens, and a rigid contact holds the gap at zero:
    not for them.

    Parameters
    ----------
    result : ImpactResult
        A solution with at least one contact interval.

    Returns
    -------
    float
    """
    t, gap = np.asarray(result.t, dtype=float), np.asarray(result.gap, dtype=float)
    start, end = result.contact_intervals[0]
    i_start, i_end = int(np.searchsorted(t, start)), int(np.searchsorted(t, end))

    def crossing(j):                 # gap[j - 1] and gap[j] on either side of zero
        g0, g1 = gap[j - 1], gap[j]
        return t[j - 1] + (t[j] - t[j - 1]) * g0 / (g0 - g1) if g0 != g1 else t[j]

    # the closing: the first sample at or after the interval's start where the gap is
    # no longer positive (the interval may start a sample before it, or at t = 0 closed)
    closed = i_start + np.flatnonzero(gap[i_start:i_end + 1] <= 0.0)
    if closed.size and closed[0] > 0 and gap[closed[0] - 1] > 0.0:
        start = crossing(int(closed[0]))
    opened = np.flatnonzero(gap[i_end:] > 0.0)
    if opened.size and i_end + opened[0] > 0 and gap[i_end + opened[0] - 1] <= 0.0:
        end = crossing(i_end + int(opened[0]))
    return float(end - start)


def _force_vanishes_with_gap(contact) -> bool:
    """Whether the contact's force is zero exactly where the gap is (Hertz, an undamped
    spring): then :func:`gap_crossing_duration` measures its duration."""
    return isinstance(contact, Hertz) or (isinstance(contact, LinearSpring)
                                          and contact.damping == 0.0)


def exact_reference(case: Case) -> Reference:
    """The exact figures and force history of ``case`` on its exact models.

    Parameters
    ----------
    case : Case
        The case.

    Returns
    -------
    Reference
    """
    t0 = time.perf_counter()
    grid = np.linspace(0.0, case.t_end, 20001)
    if case.reference == "mass_on_fixed_rod":
        rod = case.body2
        ref = mass_on_fixed_rod(case.body1.mass, rod.mass, rod.transit_time, case.velocity1, grid)
        inside = grid <= ref.separation_time
        figs = {"contact_duration": ref.separation_time,
                "peak_force": float(ref.force[inside].max()), "impulse": ref.total_impulse,
                "restitution": ref.restitution}
        out = Reference(figs, grid, np.asarray(ref.force), "mass_on_fixed_rod (closed form)",
                        0.0)
    elif case.reference == "two_free_rods":
        b1, b2 = case.body1, case.body2
        ref = two_free_rods_equal_transit(b1.mass, b2.mass, b1.transit_time, case.velocity1,
                                          case.velocity2, grid)
        figs = {"contact_duration": ref.contact_duration, "peak_force": ref.force_height,
                "impulse": ref.impulse, "restitution": ref.restitution}
        out = Reference(figs, grid, np.asarray(ref.force), "two_free_rods_equal_transit "
                        "(closed form)", 0.0)
    else:
        def solve(dt):
            with warnings.catch_warnings():
                if case.richardson:     # its first-order error is extrapolated away
                    warnings.filterwarnings("ignore", r"dt=\S+ s is \S+ times the step that "
                                            "resolves these bodies", RuntimeWarning)
                return solve_impact(Body(case.body1, velocity=case.velocity1),
                                    Body(case.body2, velocity=case.velocity2),
                                    contact=case.contact, t_end=case.t_end, dt=dt,
                                    method="convolution", progress=False)

        res = solve(case.dt_exact / 2 if case.richardson else case.dt_exact)
        fine = impact_figures(res)
        figs = {k: fine[k] for k in FIGURES}
        how = f"convolution, dt = {case.dt_exact:g} s"
        if case.richardson:
            coarse_res = solve(case.dt_exact)
            coarse = impact_figures(coarse_res)
            extrapolated = ["peak_force", "impulse", "restitution"]
            if not _force_vanishes_with_gap(case.contact):
                how += " and half of it, Richardson-extrapolated (duration: the finer)"
            else:                                   # the gap is negative while pressing
                figs["contact_duration"] = gap_crossing_duration(res)
                coarse["contact_duration"] = gap_crossing_duration(coarse_res)
                extrapolated.append("contact_duration")
                how += (" and half of it, Richardson-extrapolated (duration: where the gap "
                        "crosses zero between samples)")
            for k in extrapolated:
                figs[k] = 2.0 * figs[k] - coarse[k]
        out = Reference(figs, np.asarray(res.t), np.asarray(res.force), how, 0.0)
    t, f = np.array(out.t, dtype=float), np.array(out.force, dtype=float)
    t.setflags(write=False)
    f.setflags(write=False)
    return Reference(out.figures, t, f, out.how, time.perf_counter() - t0)


# -------------------------------------------------------------------- measurement
@dataclass(frozen=True)
class Measurement:
    """How each continuum is measured (see the module docstring).

    Parameters
    ----------
    damping_ratio : float
        Viscous damping ratio of every mode of the measured truth.
    n_hits : int
        Hammer hits averaged.
    response : str
        The measured response (``"velocity"``, ...).
    noise_reference : str
        What the noise level is relative to (``"rms"``: each record's RMS).
    periods : float
        Record length in periods of the first elastic mode.
    max_lines : int
        Most lines in the band, unless ``min_periods`` needs more.
    min_periods : float
        Fewest periods of the first mode in a record (a beam's ``f_top / f1`` grows like
        ``n**2``: 5 periods take 5600 lines at 20 modes, 22 500 at 40).
    window_end : float
        The exponential window's value at the record's end.
    fs_factor : float
        Sampling rate over the band's top frequency.
    extra_modes : int
        Modes of the truth above the band.
    """

    damping_ratio: float = 1e-4
    n_hits: int = 5
    response: str = "velocity"
    noise_reference: str = "rms"
    periods: float = 50.0
    max_lines: int = 4000
    min_periods: float = 5.0
    window_end: float = 0.01
    fs_factor: float = 5.0
    extra_modes: int = 10


@dataclass(frozen=True)
class Identified:
    """One measured body: the fit, its truth, its band top (Hz), the H1 estimate's noise
    (median over the band's lines of ``|H1 / H1_noise-free - 1|``) and stage times (s)."""

    fit: ModalFit
    truth: object
    band_top_hz: float
    n_lines: int
    duration: float
    seconds: dict
    frf_noise: float = 0.0


def fit_max_order(n_modes: int, n_lines: int = 0) -> int | None:
    """The stabilization diagram's largest order for a band of ``n_modes`` modes in
    ``n_lines`` lines: None (``ModalFit``'s default, ``4 n_peaks + 16`` capped at 120) up to
    26 modes, else ``4 n_modes + 16``. The cap found 9 of a fixed rod's 40 modes (1 %
    noise, verdict "failed", modal masses 0.69 for 0.5); order 176 finds all 40 (masses
    within 0.6 %). A band of ``modalid._segments.MIN_SEGMENTED`` lines or more is fitted
    by segments of a few modes each, for which the default suits: order 176 there gave a
    beam's 40 modes plus 72 spurious ones, in three times the time (22 500 lines).

    Parameters
    ----------
    n_modes : int
        Modes in the band.
    n_lines : int
        Lines in the band.

    Returns
    -------
    int or None
    """
    from modalid._segments import MIN_SEGMENTED

    order = 4 * int(n_modes) + 16
    return order if order > 120 and n_lines < MIN_SEGMENTED else None


def measure_body(body, n_modes, noise, *, seed, measurement=Measurement(),
                 exact_noise: bool = False) -> Identified:
    """Synthetic hammer test of ``body`` covering ``n_modes`` elastic modes, identified.

    ``frf_noise`` of the result: with ``exact_noise`` the median over the band's lines of
    ``|H1 / H1_noise-free - 1|`` (a second, noise-free hammer test: as costly as the
    first), else the fit's own estimate of the data's scatter (``report_
    ["noise_median_relative"]``; 0.94 % where the exact figure is 1.2 %, fixed rod, 10
    modes, 1 % noise).

    Parameters
    ----------
    body : object
        An exact model (``data_synth``).
    n_modes : int
        Elastic modes the band covers.
    noise : float
        Noise level (a share, 0.01 for 1 %).
    seed : int, keyword-only
        The hammer test's seed (:func:`body_seed`).
    measurement : Measurement, keyword-only
        How it is measured.
    exact_noise : bool, keyword-only
        Measure ``frf_noise`` against a noise-free test (twice the cost).

    Returns
    -------
    Identified
        The fit, its model and the measurement's figures.
    """
    ms = measurement
    t0 = time.perf_counter()
    truth = lightly_damped(body, n_modes + ms.extra_modes, ms.damping_ratio)
    w = np.sort(truth.modes["omega_n"].to_numpy())
    w = w[w > 0]
    top = 0.5 * (w[n_modes - 1] + w[n_modes]) / (2 * math.pi)
    # 50 periods of the first mode, at most 4000 lines, but at least 5 periods: a beam's
    # f_top/f1 grows like n^2 (3.6 periods in 4000 lines at 20 modes: mode 1 1.4 % high,
    # at 40 modes 0.9: modes 1-3 missed); a tester lengthens the record to resolve mode 1
    duration = min(ms.periods * 2 * math.pi / w[0],
                   max(ms.max_lines / top, ms.min_periods * 2 * math.pi / w[0]))
    fs = ms.fs_factor * top
    decay = -math.log(ms.window_end) / duration

    def estimate(level):
        test = synthetic_hammer_test(truth, fs, duration, n_hits=ms.n_hits,
                                     pulse_width=0.5 / top, noise=level, response=ms.response,
                                     seed=seed, anti_alias=True,
                                     noise_reference=ms.noise_reference)
        with warnings.catch_warnings():     # pulses of ~2.5 samples: noise may look like a
            warnings.simplefilter("ignore")     # second hit
            return frf_from_hammer(test.force, test.response, fs, response_type=ms.response,
                                   exponential_decay=decay)

    est = estimate(noise)
    t1 = time.perf_counter()
    frf = est.frf.band((1.0 / duration, top))
    frf_noise = None
    if noise and exact_noise:
        clean = estimate(0.0).frf.band((1.0 / duration, top))
        frf_noise = float(np.median(np.abs(frf.values / clean.values - 1.0)))
    t2 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit(weighting="noise", max_order=fit_max_order(n_modes, frf.freq_hz.size),
                       **est.fit_options()).fit(frf)
    t3 = time.perf_counter()
    if frf_noise is None:
        frf_noise = float(fit.report_.get("noise_median_relative", math.nan)) if noise else 0.0
    return Identified(fit, truth, top, frf.freq_hz.size, duration,
                      {"hammer": t1 - t0, "frf": t2 - t1, "identify": t3 - t2}, frf_noise)
