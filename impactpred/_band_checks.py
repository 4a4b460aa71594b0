"""What of a predicted impact lies outside an identified body's measured band: the contact
force's energy above and below it, and how long the run relies on the model below it.

:func:`band_reach` is :func:`impactpred.predict`'s check of the band: a
:class:`BandWarning` for what the prediction relies on outside the data (the continuation
or residual terms above the band; below it, a rigid-body line or a lower residual
pseudo-mode, by the force's energy there and by the time the run goes on after the first
contact).
"""

from __future__ import annotations

import warnings

import numpy as np

from .result import ImpactResult

__all__ = ["BandWarning", "force_energy_above", "force_energy_below", "band_reach",
           "resolved_force"]

#: a run sampled more coarsely than its shortest contact over this many steps does not
#: resolve the force's spectrum (a long ``t_end`` coarsens the automatic output step)
RESOLVED_STEPS = 32
#: ... and is solved again for the spectrum up to this many spans of its contacts
SHARE_SPANS = 64


class BandWarning(UserWarning):
    """A prediction relies on a body's model outside its measured band: a good part of the
    contact force's spectrum lies above or below the band, or the run outlasts what the
    band vouches for below it."""


def _force_samples(result: ImpactResult) -> tuple:
    """``(samples, dt)``: the contact force resampled on a uniform grid over the run (at
    least 4096 samples, a power of two), each Dirac impulse as one sample of
    ``impulse / dt``."""
    t, f = result.t, result.force
    n = max(4096, int(2 ** np.ceil(np.log2(t.size))))
    grid = np.linspace(t[0], t[-1], n)
    dt = grid[1] - grid[0]
    signal = np.interp(grid, t, f)
    for time, impulse in result.dirac_impulses:
        signal[min(int(round(time / dt)), n - 1)] += impulse / dt
    return signal, dt


def resolved_force(result: ImpactResult, resolve) -> ImpactResult:
    """The solved impact whose force spectrum the band's shares are read from: ``result``
    where its samples resolve its longest contact, else ``resolve(t_end)``, the same impact
    solved up to :data:`SHARE_SPANS` spans of its contacts at its automatic step.

    A long ``t_end`` coarsens the automatic output step (4e6 samples at most): at
    ``t_end = 1e6`` s the force is sampled every 0.25 s, a contact of a second has no
    spectrum, and the continuation's rule saw no energy above a 6 Hz band and turned the
    continuation off (16 contacts, e 0.455, where ``t_end = 4`` s gave one contact and
    0.451 with it). Read from the run up to its contacts' spans, the shares do not depend
    on ``t_end``. A run whose contacts reach its end, or without contacts of a duration,
    is its own record.
    """
    intervals = np.asarray(result.contact_intervals, dtype=float).reshape(-1, 2)
    durations = intervals[:, 1] - intervals[:, 0]
    durations = durations[durations > 0]
    if durations.size == 0 or result.dt <= durations.max() / RESOLVED_STEPS:
        return result              # the longest contact, the force's bulk, is resolved
    span = intervals[-1, 1] - intervals[0, 0]
    t_short = intervals[-1, 1] + (SHARE_SPANS - 1) * span
    if t_short >= result.t[-1]:
        return result
    try:
        return resolve(t_short)
    except (ValueError, RuntimeError):    # a run the shorter t_end refuses: its own record
        return result


def force_energy_above(result: ImpactResult, freq_hz: float) -> float:
    """Share (0-1) of the contact force's spectral energy above ``freq_hz``:
    ``1 - force_energy_below(result, freq_hz)``, 0 for a force that is zero throughout.

    (It was read on the run's own spectral lines, ``1/t_end`` apart, without the DC
    line: a band top below ``1/t_end`` saw the whole energy above it, 100 % where 4 %
    lay there, and the continuation was turned on for it.)
    """
    return _energy_split(result, freq_hz)[1]


def force_energy_below(result: ImpactResult, freq_hz: float) -> float:
    """Share (0-1) of the contact force's spectral energy below ``freq_hz``.

    The force resampled on a uniform grid (Dirac parts white over the grid's band), its
    record padded with zeros (the force after the run: none, unless the bodies are still
    in contact at its end) until its spectral lines lie at most ``freq_hz / 16`` apart
    (padded to 2**22 samples at most), so that a low ``freq_hz`` is resolved: the run's
    own length, 1/t_end apart, may not. Each line holds the energy of its own width (the
    DC line half of one), read linearly within the line at ``freq_hz``. The share above,
    :func:`force_energy_above`, is the rest.

    Parameters
    ----------
    result : ImpactResult
        A solved impact.
    freq_hz : float
        The frequency (Hz) below which the energy is counted.

    Returns
    -------
    float
        The share, 0 for a force that is zero throughout.
    """
    return _energy_split(result, freq_hz)[0]


def _energy_split(result: ImpactResult, freq_hz: float) -> tuple[float, float]:
    """``(below, above)``: the shares of :func:`force_energy_below` and
    :func:`force_energy_above` (both 0 for a force that is zero throughout)."""
    signal, dt = _force_samples(result)
    lines = 16.0 / (freq_hz * dt) if freq_hz > 0 else 1.0      # lines freq_hz / 16 apart
    padded = max(signal.size, min(int(2 ** np.ceil(np.log2(lines))), 2 ** 22))
    spectrum = np.abs(np.fft.rfft(signal, padded)) ** 2
    spectrum[0] *= 0.5                   # the DC line holds [0, df/2), the others df each
    df = 1.0 / (padded * dt)
    # the energy up to each line's upper edge, read at freq_hz (linear within a line)
    edges = (np.arange(spectrum.size) + 0.5) * df
    cumulative = np.cumsum(spectrum)
    total = float(cumulative[-1])
    if total <= 0:
        return 0.0, 0.0
    below = float(np.interp(freq_hz, np.concatenate(([0.0], edges)),
                            np.concatenate(([0.0], cumulative))) / total)
    return below, 1.0 - below


#: how far a figure's interval may reach, re-identified on 80 % of each band
#: (:func:`warn_unsettled`), before the band is said not to settle the prediction: the
#: restitution's (absolute), the impulse's and the duration's (relative). The peak
#: force's holds the wave front's allowance: not checked.
UNSETTLED = {"restitution": 0.05, "impulse": 0.05, "contact_duration": 0.10}


def warn_unsettled(check, figures, bodies=()) -> list:
    """A :class:`BandWarning` where the bands do not settle the prediction; returns what
    did not settle (figure names, ``"outcome"``, ``"unchecked"``).

    ``check`` is an :class:`~impactpred.uncertainty.UncertaintyBand` without draws nor tail
    (the cut band's change only); ``figures`` the prediction's; ``bodies`` the numbers
    (1-based) of the bodies re-identified on the cut band. Said: a figure whose interval
    is wider than :data:`UNSETTLED` or not finite; an outcome that changes in kind on the
    cut band (another number of contacts, a figure defined in one run only: outside any
    interval); a body whose cut-band model could not be built or solved (not checked).

    A fixed rod's hammer test at 1 % noise predicted a restitution of 0.511 for the
    truth's 0.690 ("ok", a band warning of 2.3 % of the force's energy above the band
    only): re-identified on 80 % of its band it gave 0.421, and its interval reached
    from -0.10 to 1. The same test with another noise seed: 0.707, interval +-0.005.
    """
    loose, names = [], []
    for name, limit in UNSETTLED.items():
        value, low, high = figures.get(name), check.low.get(name), check.high.get(name)
        if value is None or low is None or high is None:
            continue
        scale = 1.0 if name == "restitution" else abs(value)
        if not np.all(np.isfinite([value, low, high])):
            loose.append(f"{name} {value:.4g} (from {low:.4g} to {high:.4g}: not finite)")
        elif max(high - value, value - low) > limit * scale:
            loose.append(f"{name} {value:.4g} (from {low:.4g} to {high:.4g})")
        else:
            continue
        names.append(name)
    parts = []
    if loose:
        cuts = "; ".join(f"{label}: restitution {figs['restitution']:.4g}"
                         for label, figs in check.variants
                         if "band" in label and figs.get("restitution") is not None)
        parts.append(", ".join(loose) + (f" ({cuts})" if cuts else ""))
    if check.outcome_changes:
        parts.append("its outcome changes in kind on the cut band ("
                     + "; ".join(check.outcome_changes) + ")")
        names.append("outcome")
    solved = {label.split(" ", 1)[0] for label, _ in check.variants if " band " in label}
    unchecked = [b for b in bodies if f"body{b}" not in solved]
    if parts:
        warnings.warn(f"the measured bands do not settle this prediction: {'; '.join(parts)}"
                      "; it rests on what the bands do not hold: measure a wider band or "
                      "more hits, or see the whole band with uncertainty=True", BandWarning,
                      stacklevel=3)
    if unchecked:
        which = " and ".join(f"body {b}" for b in unchecked)
        warnings.warn(f"the band check could not solve {which} re-identified on the cut "
                      "band: this prediction is not checked for it", BandWarning,
                      stacklevel=3)
        names.append("unchecked")
    return names


def band_reach(result, fits, notes, band_tolerance, lower, record) -> tuple:
    """Per identified body, the shares of the force's energy above and below its band
    (None for the other bodies; read from ``record``, :func:`resolved_force`'s), with a
    :class:`BandWarning` for each above
    ``band_tolerance``: above, always; below, where the model has a term standing for
    what lies below the band and more than it is trusted with lies there (``lower``: per
    body, ``(words, share, vouched)`` naming that term, the share of the energy it is
    trusted with and whether the band vouches for it, ``(None, inf, True)`` without one;
    ``impactpred.predict._lower_terms``), or, for a term the band does not vouch for,
    where the run goes on after the first contact past a quarter period of the band's
    bottom (:func:`_outlasts_band_bottom`)."""
    above: list[float | None] = []
    below: list[float | None] = []
    for i, (fit, note, (terms, trusted, vouched)) in enumerate(zip(fits, notes, lower)):
        if fit is None:
            above.append(None)
            below.append(None)
            continue
        low, top = fit.report_["band_hz"]
        share = force_energy_above(record, top)
        above.append(share)
        if share > band_tolerance:
            there = ("its continuation above the band" if note.startswith("on")
                     else "the model's residual terms there")
            warnings.warn(f"body {i + 1}: {100 * share:.1f} % of the contact force's energy "
                          f"lies above its measured band ({top:.4g} Hz); the prediction "
                          f"relies on {there}", BandWarning, stacklevel=3)
        share = force_energy_below(record, low)
        below.append(share)
        if share > trusted:
            warnings.warn(f"body {i + 1}: {100 * share:.1f} % of the contact force's energy "
                          f"lies below its measured band ({low:.4g} Hz), where its model "
                          f"has only {terms}: the prediction relies on it there; an FRF "
                          "measured from below both the body's first mode and the bulk of "
                          "the force's spectrum would settle it", BandWarning, stacklevel=3)
        elif not vouched:
            _outlasts_band_bottom(result, i + 1, low, terms)
    return above, below


def _outlasts_band_bottom(result, body: int, low: float, terms: str) -> None:
    """A :class:`BandWarning` when the run goes on after its first contact for more than a
    quarter period of the band's bottom ``low`` (Hz), where the body's model below the
    band is ``terms`` (a term the band does not vouch for): a mode below the band turns
    the body back after a quarter of its period, longer than that; the model's term need
    not (a rigid-body line never does). What the force's energy below the band cannot
    show: the model's own run has no late contact to put energy there. A cantilever
    measured from 2.1 times its first mode, its mode taken for a rigid body, struck by a
    mass for 30 s: 0.8 % of the force's energy below the band, restitution 0.17 for the
    exact 0.34 (the beam comes back and chatters against the mass)."""
    starts = [start for start, _ in result.contact_intervals]
    if not starts or not low > 0:
        return
    after = float(result.t[-1]) - min(starts)
    quarter = 0.25 / low
    if after > quarter:
        warnings.warn(f"body {body}: the run goes on {after:.3g} s after the first contact, "
                      f"{after / quarter:.3g} times a quarter period of the bottom of its "
                      f"measured band ({low:.4g} Hz: {quarter:.3g} s), below which its model "
                      f"has only {terms}: the motion after that (a return, later contacts, "
                      "the final restitution) relies on it; an FRF measured from below the "
                      "body's first mode, or a t_end within that time of the contact, "
                      "would settle it", BandWarning, stacklevel=4)
