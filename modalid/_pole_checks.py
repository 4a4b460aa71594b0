"""Poles the estimator missed, and poles to drop: the checks behind
:meth:`modalid.fit.ModalFit`'s refinement (a mixin of :class:`modalid._frf_pipeline.
FRFPipeline`).

* :meth:`PoleChecks._missed_mode` adds a mode where the weighted residual peaks, when a
  resonance explains the peak (:meth:`PoleChecks._explains_peak`, judged on the lines
  around it against the data's noise, with ``missed_modes="strict"``; by the information
  criterion on the whole cost with ``"dense"``);
* :meth:`PoleChecks._worst_pole` names the physical pole to drop first: a negative modal
  mass under passivity, a pole that left the band, a duplicate, an insignificant one, one
  that changes the fit on its own lines by no more than the data's noise
  (:meth:`PoleChecks._local_evidence`).

The methods read the estimator's settings and its refinement (``self._refine``,
``self._linear_fit``, ``self._model_weights``, ``self._buffers``), which
:class:`modalid._frf_pipeline.FRFPipeline` provides.
"""

from __future__ import annotations

import numpy as np

from ._band import noise_model
from ._lsfd import evaluate, refine_varpro, removal_cost, split_coefficients
from ._verdict import missed_peak_lines

__all__ = ["PoleChecks", "line_noise", "local_evidence", "pole_lines"]


def line_noise(h, noise, coherence=None):
    """Standard deviation of each line of ``h`` (receptance, any shape): ``noise`` =
    ``(sigma_rel, floor)`` of :func:`modalid._band.noise_model`, the proportional part at
    most the H1 estimator's bound for one average, ``sqrt((1 - g)/g)``, where the data's
    coherence ``g`` (shape of ``h``) is given (see :meth:`PoleChecks._line_noise`)."""
    sigma_rel, floor = noise
    if coherence is not None:
        g = np.clip(coherence, 1e-6, 1.0)
        sigma_rel = np.minimum(sigma_rel, np.sqrt(np.maximum(1.0 - g, 0.0) / g))
    return np.hypot(sigma_rel * np.abs(h), floor)


def pole_lines(omega, p, spacing):
    """The lines (bool, shape of ``omega``) a pole ``p`` acts on: within five half-power
    half-widths ``|Re p|`` of its frequency, or five lines of ``spacing`` (rad/s), the
    wider."""
    return np.abs(omega - p.imag) <= max(5.0 * spacing, 5.0 * abs(p.real))


def local_evidence(omega, h, w, sigma, poles, r, model):
    """Per pole, summed over the rows of ``h`` (shape (rows, lines)): how much worse the
    model fits the lines the pole acts on without its term (:func:`pole_lines`; nothing
    refitted), over that row's noise there,
    ``sum |w (h - model + term)|^2 - sum |w (h - model)|^2`` over ``sum (w sigma)^2``.
    ``w``, ``sigma``, ``model``: shape of ``h``; ``r``: residues (rows, poles). A sum over
    the rows, not a noise-weighted mean: a mode seen in one row is not diluted by the
    others. Below 1 the data cannot tell the pole from their noise
    (:meth:`PoleChecks._local_evidence`)."""
    spacing = float(np.median(np.diff(omega)))
    evidence = np.empty(poles.size)
    for k, p in enumerate(poles):
        near = pole_lines(omega, p, spacing)
        s = 1j * omega[near]
        term = (r[:, k, None] / (s - p)[None, :]
                + np.conj(r[:, k, None]) / (s - np.conj(p))[None, :])
        wk, res = w[:, near], h[:, near] - model[:, near]
        gain = (np.sum(np.abs(wk * (res + term)) ** 2, axis=1)
                - np.sum(np.abs(wk * res) ** 2, axis=1))
        noise = np.maximum(np.sum((wk * sigma[:, near]) ** 2, axis=1), 1e-300)
        evidence[k] = float(np.sum(gain / noise))
    return evidence


#: the share of the band's lines at either end that the missed-mode search leaves to the
#: pseudo-modes (but for a resonance missed outright there: :func:`_edge_lines`)
END_SHARE = 0.02


def _at_end(k, n: int):
    """Whether line ``k`` (an index, or an array of them) of ``n`` lies in the
    :data:`END_SHARE` of the lines at either end of the band."""
    return np.minimum(k, n - 1 - k) < int(END_SHARE * n)


def _edge_lines(h, resid):
    """The lines (bool, shape of ``h``) the missed-mode search leaves alone: the 2 % at
    either end of the band (the pseudo-modes' ground), but for the three lines around a
    resonance of the data there that the model, ``h - resid``, misses outright
    (:func:`modalid._verdict.missed_peak_lines`: a sharp distinct peak of the data,
    missed by more than half of it and ten times the scatter at its line and both
    neighbours), judged here in receptance, the quantity fitted (the verdict judges the
    data's own). A cantilever's accelerance from 0.52 Hz lost its 0.929 Hz mode, at line
    11 of 2000, 194 in the data against 0.3 in the model. The broad humps a one-hit
    hammer record has at 30-60 Hz stay out (taken as modes, at damping 0.1-0.15, they
    had the transfer FRF's negative mass line turn positive); its sharp 18 Hz resonance
    is tried, and the trial, drawn to the hump beside it, rejected."""
    edge = _at_end(np.arange(h.size), h.size)
    missed = missed_peak_lines(h, h - resid)
    for k in missed[edge[missed]]:
        edge[max(k - 1, 0):k + 2] = False
    return edge


class PoleChecks:
    """Missed modes and pole drops of the FRF refinement (see the module docstring)."""

    def _missed_mode(self, omega, h, w, poles, kinds, x, info, terms, tried):
        """Add a mode the pole estimator missed, where the weighted residual has a peak.

        The residual power, averaged over 3 lines, must exceed 14 times its median (for
        noise alone a 1e-9 event) at a frequency 0.3 % or more from a mode found before
        (a close pair's partner lies 0.5-1 % away; a 2 % exclusion hid the 4101 Hz dip
        beside the 4128 Hz mode of a real hammer test) and three half-power half-widths
        from a peak rejected before (``tried``: ``(omega, radius)`` pairs, appended to
        here; retrying a rejected peak's shoulders used up the search's misses before it
        reached the next peak), away from the 2 % of the lines at either end (the
        pseudo-modes' ground) but for a sharp resonance of the data the model misses
        outright there (:func:`_edge_lines`: tried from its own line, once, a rejection
        costing the search no miss). A pole is placed there,
        refined quickly (:meth:`_trial_mode`), and kept when it passes
        :meth:`_worst_pole`, lies two lines or more from every other mode (closer ones
        cannot be resolved: a sharp peak's shape, not a mode) and, with
        ``missed_modes="strict"``, the weighted residual around it halves
        (:meth:`_explains_peak`: a resonance accounts for most of its own peak, whatever
        else the band still misses, and for much more than the data's noise there); with
        ``"dense"``, the cost drops by more than ``4 ln(n)`` residual variances (``n`` real
        data, the variance the cost before it over ``n`` less four per pole: the
        information criterion of the pole selection) and its damping ratio, the window's
        removed, is under 0.1 (a resonance, not a broad trend of the residual). A peak
        narrower than its lines starts from its own three lines
        (:meth:`_sharp_peak_pole`); then (or else) the pole starts at the residual
        peak's half-power width (:meth:`_peak_half_width`; a pole of 1 % damping can stay
        stuck on a sharp peak) and, if that fails, at 1 % damping; ``"dense"`` tries
        these two in the other order.

        Returns the poles, kinds, coefficients and information with the mode, or as they
        were, and a list of notes: one note when a mode was added, empty when the peak's
        mode was rejected (the caller may try the next peak), ``None`` when no peak is
        left above the threshold.
        """
        r, _, u, d = split_coefficients(x, poles.size, terms)
        resid = h - evaluate(omega, poles, r, (), (), u, d, terms.rigid_shift)
        wm = self._model_weights(omega, poles, x, terms, w)
        e2 = np.convolve(np.abs(resid * wm) ** 2, np.ones(3) / 3, mode="same")
        # against the residual's median, or its rounding level (noise-free data: 0 / 0)
        scale = max(np.median(e2), (1e3 * np.finfo(float).eps) ** 2
                    * float(np.median(np.abs(h * wm) ** 2)))
        if not scale > 0.0:
            return poles, kinds, x, info, None
        e2 /= scale
        e2[_edge_lines(h, resid)] = 0.0
        for wt, radius in tried:
            e2[np.abs(omega - wt) < radius] = 0.0
        k = int(np.argmax(e2))
        if e2[k] < 14.0:
            return poles, kinds, x, info, None
        k0, at_end = k, bool(_at_end(k, e2.size))
        if at_end:            # a missed peak at an end of the band: from its own line
            k = max(k - 1, 0) + int(np.argmax(np.abs(resid[max(k - 1, 0):k + 2])))
        wk = omega[k]
        # from the peak's own half-power width, then 1 % damping ("dense": the other way)
        narrow = self._peak_half_width(omega, resid, k)
        # a rejected peak hides three of its half-widths (its shoulders are the same
        # feature, not a next peak), a mode found only 0.3 % (its close partner may lie
        # there)
        tried.append((wk, max(0.003 * wk, 3.0 * narrow)))
        if at_end:            # tried once: its line, the line the search chose, beside them
            beside = 1.5 * float(np.max(np.diff(omega[max(k - 2, 0):k + 3])))
            tried[-1] = (wk, max(tried[-1][1], abs(omega[k0] - wk) + beside))
        starts = [complex(-d, wk) for d in ((0.01 * wk, narrow) if narrow < 0.005 * wk
                                             else (0.01 * wk,))]
        if self.missed_modes != "dense":
            starts = starts[::-1]
        sharp = self._sharp_peak_pole(omega, resid, k)
        if sharp is not None:          # a peak narrower than its lines: its own pole first
            starts.insert(0, sharp)
        for start in starts:
            out = self._trial_mode(omega, h, w, poles, kinds, x, terms, resid, start, narrow)
            if out is not None:
                break
        else:
            if at_end:        # costs the search no miss: on to the next peak (the line
                # chosen is hidden now: the unmasked lines at the ends run out)
                return self._missed_mode(omega, h, w, poles, kinds, x, info, terms, tried)
            return poles, kinds, x, info, []
        tried[-1] = (wk, 0.003 * wk)
        note = f"added a mode the pole estimator missed, at {wk / (2 * np.pi):.6g} Hz"
        return (*out, [note])

    def _trial_mode(self, omega, h, w, poles, kinds, x, terms, resid, start, width):
        """The model with a mode started at ``start`` added and refined quickly, as
        ``(poles, kinds, x, info)``, if :meth:`_missed_mode`'s tests keep it; else None.
        ``x``: the model's linear unknowns; ``width``: the residual peak's half-power
        half-width (rad/s).

        With ``missed_modes="strict"`` the trial is a local question, answered on the
        lines around the peak (:meth:`_local_trial`); a mode kept joins the model with the
        local fit's poles (:meth:`_join`, no refinement over the band: the full one after
        the search does that) unless the local fit moved another mode away
        (:meth:`_stayed`), when the trial is refined quickly over the whole band from the
        old poles. ``"dense"`` refines every trial over the band."""
        if self.missed_modes == "strict":
            local = self._local_trial(omega, h, w, poles, kinds, x, terms, start, width)
            if local is None:
                return None
            inside, refined, new = local
            if self._stayed(omega, poles[inside], np.delete(refined, new)):
                return self._join(omega, h, w, poles[~inside], kinds[~inside], terms, refined)
        trial = np.append(poles, start)
        kinds_t = np.append(kinds, "mode")
        order = np.argsort(np.where(kinds_t == "mode", np.abs(trial), np.inf), kind="stable")
        trial, kinds_t = trial[order], kinds_t[order]
        poles_t, x_t, info_t = self._refine(omega, h, w, trial, kinds_t, terms, quick=True)
        if self.missed_modes == "strict":                 # judged by _local_trial
            return poles_t, kinds_t, x_t, info_t
        new = int(np.flatnonzero(order == trial.size - 1)[0])
        worst, _ = self._worst_pole(omega, h, w, poles_t, x_t, info_t, kinds_t, terms, only=new)
        cost = np.sum(np.abs(resid * w) ** 2)
        added = poles_t[new]
        n_real = 2 * omega.size
        variance = cost / max(n_real - 4 * poles.size, 1)
        keep = (info_t["cost"] <= cost - 4 * np.log(n_real) * variance
                and self._apart(omega, poles_t, kinds_t, new)
                and (-added.real - self._shift) / abs(added) < 0.1)
        if not keep or worst is not None:
            return None
        return poles_t, kinds_t, x_t, info_t

    @staticmethod
    def _apart(omega, poles, kinds, new):
        """Is the pole ``new`` two lines or more from every other mode?"""
        others = np.abs(np.delete(poles, new)[np.delete(kinds, new) == "mode"])
        return not np.any(np.abs(others - abs(poles[new])) < 2 * np.median(np.diff(omega)))

    def _local_trial(self, omega, h, w, poles, kinds, x, terms, start, width,
                     half_lines=64):
        """Does a mode started at ``start`` earn its place? Judged where it acts: on the
        lines within ``half_lines`` lines (or 20 half-power half-widths ``width`` of the
        residual's peak, if wider) of it, with the modes outside those lines held as they
        are and subtracted from the data, the modes inside refined quickly with the new one
        (:func:`modalid._lsfd.refine_varpro`, the data's weights, 15 steps at most) and
        the pseudo-modes (poles held) and the extra terms refitted with them.
        Kept when the weighted cost on these lines falls below that of the same local
        model without the mode (its linear unknowns refitted there), the mode passes
        :meth:`_worst_pole` (on these lines), lies two lines or more from every other
        mode and :meth:`_explains_peak` against that model's residual. A tenth of the band's lines
        and a few poles: a rejected trial costs a small part of a refinement over the
        band.

        Returns ``None`` when the mode is not kept, else ``(inside, refined, new)``: the
        model's modes refined with it (bool, shape of ``poles``), the local fit's poles
        (those modes and the new one, sorted by modulus) and the new one's index there."""
        spacing = float(np.median(np.diff(omega)))
        half = max(half_lines * spacing, 20.0 * width)
        lines = np.abs(omega - start.imag) <= half
        mode = kinds == "mode"
        inside = mode & (np.abs(poles.imag - start.imag) <= half)
        outside = mode & ~inside
        r, *_ = split_coefficients(x, poles.size, terms)
        background = np.zeros(omega.size, complex)     # the modes held, where judged
        background[lines] = evaluate(omega[lines], poles[outside], r[outside], (), (), 0.0,
                                     0.0, terms.rigid_shift)
        modes_l = np.sort_complex(np.append(poles[inside], start))
        modes_l = modes_l[np.argsort(np.abs(modes_l), kind="stable")]
        new = int(np.flatnonzero(modes_l == start)[0])
        # the pseudo-modes (held) and the extra terms are refitted with the local modes:
        # fitted without the peak, they took up some of its skirt (a mode of zeta 2e-4 at
        # 163 Hz on 0.5 Hz lines: held, their error on these lines was its skirt's size)
        local = np.concatenate([modes_l, poles[~mode]])
        kinds_l = np.concatenate([np.full(modes_l.size, "mode"), kinds[~mode]])
        hold = kinds_l != "mode"
        lo, hi = self._imag_bounds(kinds_l, omega, local)
        kw = dict(imag_lo=lo, imag_hi=hi, hold=hold, passive=self._passive_on,
                  buffers=self._buffers, with_std=not self._relative(),
                  stat_tol=0.1 if self._relative() else 1e-4, max_iter=15)
        if self.max_real is not None:
            kw["max_real"] = self.max_real
        om, hl, wl = omega[lines], (h - background)[lines], w[lines]
        # what the new mode is judged against: the same local model without it, its
        # linear unknowns refitted on these lines (a gain of that refit is not the mode's)
        without = np.delete(local, new)
        _, x_0, info_0 = refine_varpro(om, hl, wl, without, terms, hold=np.ones(without.size,
                                       bool), passive=self._passive_on,
                                       buffers=self._buffers, with_std=False, max_iter=0)
        r_0, c_0, u_0, d_0 = split_coefficients(x_0, without.size, terms)
        resid_0 = np.zeros(omega.size, complex)
        resid_0[lines] = hl - evaluate(om, without, r_0, terms.real_poles, c_0, u_0, d_0,
                                       terms.rigid_shift)
        local, x_l, info = refine_varpro(om, hl, wl, local, terms, **kw)
        if info["cost"] >= info_0["cost"]:
            return None
        everything = np.concatenate([local[~hold], poles[outside]])
        if not self._apart(omega, everything, np.full(everything.size, "mode"), new):
            return None
        worst, _ = self._worst_pole(om, hl, wl, local, x_l, info, kinds_l, terms, only=new)
        if worst is None and self._explains_peak(omega, h, w, resid_0, local, x_l, terms,
                                                 new, lines=lines, background=background):
            return inside, local[~hold], new
        return None

    @staticmethod
    def _stayed(omega, before, after):
        """Did the modes a kept local trial refined with its new one (``before`` ->
        ``after``, complex, same order) stay within three half-power half-widths (or
        three lines) of where they were? Else one moved onto another feature (a step in
        the data) to make room for the new mode, which the band's fit would not do."""
        spacing = float(np.median(np.diff(omega)))
        return bool(np.all(np.abs(after - before) <= 3.0 * np.maximum(-before.real, spacing)))

    def _join(self, omega, h, w, poles, kinds, terms, local):
        """The model ``poles`` (the modes a local trial refined taken out) with the local
        trial's modes ``local`` put in, its linear unknowns solved over the band with every
        pole held: the search goes on from there, and the full refinement after it moves
        the poles. Returns ``(poles, kinds, x, info)``, ``info["quick"]`` set."""
        poles = np.concatenate([poles, local])
        kinds = np.concatenate([kinds, np.full(local.size, "mode")])
        order = np.argsort(np.where(kinds == "mode", np.abs(poles), np.inf), kind="stable")
        poles, kinds = poles[order], kinds[order]
        poles, x, info = self._linear_fit(omega, h, w, poles, terms)
        info["quick"] = True
        return poles, kinds, x, info

    @staticmethod
    def _sharp_peak_pole(omega, resid, k):
        """The pole of a residual peak at line ``k`` narrower than its lines, from the peak
        line and its two neighbours; None for a peak wider than that.

        Near a lightly damped resonance the residual is ``R / (i omega - p)`` plus a
        background that varies slowly, so its reciprocal is linear in ``i omega``: a line
        through the three lines' reciprocals (complex least squares) gives ``p`` as its
        root, between the lines where the peak's shape puts it, and its decay from the
        reciprocal's imaginary part. A half-power start (at least half a line wide) lets a
        mode whose width is a fraction of a line refine away from its peak (a mode of
        zeta 2e-4 on 0.5 Hz lines at 163 Hz went to 165-172 Hz and was lost). Used when
        both neighbours lie below the peak's half power and the root within a line of the
        peak; the decay is kept between a thousandth and a half of a line.
        """
        if k < 1 or k + 1 >= omega.size:
            return None
        mag = np.abs(resid[k - 1:k + 2])
        if mag[1] < np.sqrt(2.0) * max(mag[0], mag[2]) or np.any(mag == 0.0):
            return None
        s = 1j * omega[k - 1:k + 2]
        design = np.column_stack([np.ones(3), s])
        (a, b), *_ = np.linalg.lstsq(design, 1.0 / resid[k - 1:k + 2], rcond=None)
        if b == 0:
            return None
        p = -a / b
        spacing = float(np.median(np.diff(omega)))
        if not abs(p.imag - omega[k]) <= spacing:
            return None
        return complex(-float(np.clip(-p.real, 1e-3 * spacing, 0.5 * spacing)), p.imag)

    @staticmethod
    def _peak_half_width(omega, resid, k):
        """Half-power half-width (rad/s) of the residual's peak at line ``k``: where
        ``|resid|`` first falls below ``1/sqrt(2)`` of the peak on either side, half the
        distance between them; at least half a line, at most 1 % of the frequency (the
        start of a missed mode's damping: a lightly damped mode refines from near its own
        damping, where one of 1 % can stay stuck on a sharp peak)."""
        mag = np.abs(resid)
        below = mag < mag[k] / np.sqrt(2.0)
        right = np.flatnonzero(below[k:])
        left = np.flatnonzero(below[:k + 1][::-1])
        hi = omega[k + right[0]] if right.size else omega[-1]
        lo = omega[k - left[0]] if left.size else omega[0]
        spacing = float(np.median(np.diff(omega)))
        return float(np.clip(0.5 * (hi - lo), 0.5 * spacing, 0.01 * omega[k]))

    def _explains_peak(self, omega, h, w, resid, poles, x, terms, new, lines=None,
                       background=None):
        """Does the mode ``new`` of the trial model ``(poles, x)`` account for the residual
        peak it was placed on? Over the lines within five half-power half-widths of it
        (five lines at least) the weighted residual ``|w (h - model)|^2`` must fall to
        half of what it was (``resid``: before the mode) or less, and by more than
        ``16 ln(n)`` times the data's own noise variance there (``n`` real data,
        :meth:`_line_noise`): the information criterion of the pole selection
        (``4 ln(n)``), judged on the lines the mode acts on instead of a cost that all the
        band's remaining misfit dilutes, with the noise's standard deviation allowed to be
        twice what :func:`modalid._band.noise_model` says (a part proportional to ``|H|``
        and a floor: robust to the curvature of dense sharp resonances, but the floor is a
        low percentile of the local scatter). Where the data carry their coherence, whose
        noise estimate is itself an upper bound, ``8 ln(n)``. A step in the data (a level
        that changes and stays) or a ripple a few times the noise is not taken for a
        mode. The noise is the lines' without the mode (its part proportional to ``|H|``
        on the model before it, not on the peak). ``lines`` (bool, shape of ``omega``):
        where the model ``(poles, x)`` holds,
        when it was fitted on those lines only; ``background`` (shape of ``omega``): the
        terms held outside that model, added to it."""
        p = poles[new]
        spacing = float(np.median(np.diff(omega)))
        near = pole_lines(omega, p, spacing)
        if lines is not None:
            near &= lines
        r, c, u, d = split_coefficients(x, poles.size, terms)
        after = h[near] - evaluate(omega[near], poles, r, terms.real_poles, c, u, d,
                                   terms.rigid_shift)
        if background is not None:
            after -= background[near]
        before = np.sum(np.abs(w[near] * resid[near]) ** 2)
        gain = before - np.sum(np.abs(w[near] * after) ** 2)
        # the noise the gain is judged against is the data's without the mode (the
        # model before it, ``h - resid``): the part proportional to |H| taken at the
        # peak's own height calls a sharp peak its own noise (vtb case2's one-line
        # resonance at 192.5 Hz, 10 times its neighbours, on a 30 % floor: 3 "sigma")
        _, measured = self._line_noise(h)
        sigma = line_noise(h - resid, self._noise,
                           self._data_band.coherence if measured else None)
        noise = np.sum((w[near] * sigma[near]) ** 2)
        factor = 8.0 if measured else 16.0
        return bool(gain >= 0.5 * before and gain > factor * np.log(2 * omega.size) * noise)

    def _line_noise(self, h):
        """Standard deviation of each line of ``h`` (the band fitted, receptance):
        :func:`modalid._band.noise_model`'s part proportional to ``|H|`` and floor; where
        the data carry their coherence ``g``, the proportional part is the H1 estimator's
        for one average, ``|H| sqrt((1 - g)/g)`` (an upper bound: averages only lower
        it), instead of the strongest lines' scatter, which on sharp resonances measures
        their curvature more than the noise (the smaller of the two per line). Returns the
        standard deviations (shape of ``h``) and whether the coherence was used.

        On a real hammer test (``benchmarks/hammer_hit5.py``) the scatter of single hits
        about their mean near 900 Hz is 0.5 % of ``|H|``, the coherence's bound 0.9 % and
        the strongest lines' scatter 2.2 %: with the latter a mode 6.5 Hz from a strong
        one was not accepted."""
        if self._noise is None:                  # the mixed weighting's, or computed once
            self._noise = noise_model(h)
        coherence = getattr(self, "_data_band", None)
        coherence = None if coherence is None else coherence.coherence
        measured = coherence is not None and coherence.shape == h.shape
        return line_noise(h, self._noise, coherence if measured else None), measured

    def _local_evidence(self, omega, h, w, poles, r, x, terms):
        """Per pole: how much worse the model fits the lines the pole acts on without it
        (within five half-power half-widths, five lines at least; the pole's term taken
        out, nothing refitted), over the data's own noise there (:meth:`_line_noise`):
        ``sum |w (h - model + term)|^2 - sum |w (h - model)|^2`` over ``sum (w sigma)^2``.

        Below 1 the data cannot tell the pole from their noise. The ``|r|/std`` test
        cannot see that where the weights trust lines more than their noise allows: at an
        antiresonance of relatively weighted data (pyuff's beam, point 2: a pole at
        414.47 Hz beside the 417 Hz antiresonance, ``|r|/std`` 6.4, evidence 0.13, every
        resonance 1000 or more; vtb case2's one resonance, at coherence 0.1-0.5, 9.2; the
        hammer test's weakest kept mode 6.6)."""
        _, _, u, d = split_coefficients(x, poles.size, terms)
        model = evaluate(omega, poles, r, (), (), u, d, terms.rigid_shift)
        sigma, _ = self._line_noise(h)
        return local_evidence(omega, h[None], w[None], sigma[None], poles, r[None],
                              model[None])

    def _worst_pole(self, omega, h, w, poles, x, info, kinds, terms, only=None):
        """The physical pole to drop first, and why (``(None, None)``: all are fine).

        A physical pole must have a positive modal mass, stay in the band, not duplicate a
        stronger one (half-power bands overlapping) and be significant, checked in that
        order; the weakest offender goes. Significant: damping < 0.3 (the structure's, a
        window's decay removed) and ``|r| > 6 std``, or else removing the mode (the rest
        refitted linearly) raises the cost by more than ``4 ln(n)`` residual variances (a
        sharp resonance on few lines has a poorly determined residue but is plainly
        there); and, judging the whole model (``only`` None), more than the data's noise
        on the lines it acts on (:meth:`_local_evidence` of 1 or more).
        """
        drop, notes = self._poles_to_drop(omega, h, w, poles, x, info, kinds, terms, only,
                                          batch=False)
        return (drop[0], notes[0]) if drop else (None, None)

    def _poles_to_drop(self, omega, h, w, poles, x, info, kinds, terms, only=None, *,
                       batch=True, spread=20.0):
        """The physical poles to drop now, with a note on each (both empty: all are
        fine): :meth:`_worst_pole`'s pole and, with ``batch`` when it goes for being not
        significant, every other pole not significant by the same test that lies more
        than ``spread`` half-power bandwidths (and lines) from it and from each other:
        such poles cannot stand in for one another, and one refit serves them all (a pole
        near one dropped could become significant once that one is gone: it waits for
        the next round)."""
        r, *_ = split_coefficients(x, poles.size, terms)
        std = info["std"]["modes"] if info["std"] is not None else np.zeros((poles.size, 4))
        with np.errstate(over="ignore"):
            t = np.abs(r) / np.maximum(np.hypot(std[:, 2], std[:, 3]), 1e-300)
        wn, zeta = np.abs(poles), -poles.real / np.abs(poles)
        # significance judges the structure's damping: the window's decay removed
        own = poles + self._shift
        zeta_own = -own.real / np.abs(own)
        mode = kinds == "mode"
        if only is not None:
            mode = mode & (np.arange(poles.size) == only)
        overlap = np.abs(wn[:, None] - wn[None, :]) < zeta[:, None] * wn[:, None] + zeta * wn
        weaker = overlap & mode[None, :] & (t[None, :] > t[:, None])
        weak = mode & (t < 6.0) & (zeta_own <= 0.3)
        if weak.any():
            gain = removal_cost(omega, h, self._model_weights(omega, poles, x, terms, w),
                                poles, terms, np.flatnonzero(weak), passive=self._passive_on,
                                buffers=self._buffers)
            weak[weak] = gain < 4 * np.log(2 * omega.size)
        evidence = (self._local_evidence(omega, h, w, poles, r, x, terms) if only is None
                    else np.full(poles.size, np.inf))
        tests = [(self._passive_on & (r.imag >= 0), "no positive modal mass"),
                 ((wn < omega[0]) | (wn > omega[-1]), "it left the band"),
                 (weaker.any(axis=1), "it duplicates a stronger pole"),
                 (weak | (zeta_own > 0.3), "not significant"),
                 (evidence < 1.0, "no more than the data's noise on its lines")]
        for i, (bad, reason) in enumerate(tests):
            bad = bad & mode
            if not bad.any():
                continue
            weakness = evidence if i == len(tests) - 1 else t     # the weakest goes first
            drop = [int(np.flatnonzero(bad)[np.argmin(weakness[bad])])]
            if batch and i >= len(tests) - 2:                     # not significant
                spacing = float(np.median(np.diff(omega)))
                reach = spread * np.maximum(-poles.real, spacing)
                for j in np.flatnonzero(bad)[np.argsort(weakness[bad])]:
                    if all(abs(wn[j] - wn[i]) > reach[i] + reach[j] for i in drop):
                        drop.append(int(j))
            figure = ("evidence {:.3g}" if weakness is evidence else "|r|/std = {:.3g}")
            notes = [f"dropped the pole at {wn[k] / (2 * np.pi):.6g} Hz: {reason} "
                     f"({figure.format(weakness[k])}, damping {zeta_own[k]:.3g})"
                     for k in drop]
            return drop, notes
        return [], []
