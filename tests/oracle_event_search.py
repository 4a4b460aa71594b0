"""Python reference of the exact engine's certified event search (the test oracle).

:func:`first_event` is the search that :func:`impactpred.engine.search.first_event` runs
compiled: the same levels, certification, last-level pieces, crossings (dips included),
root location and geometric grid at a phase that starts on an event; only the rounding
differs (BLAS products, ``brentq`` for the dips' minima). The engine itself runs the
compiled search only (:func:`impactpred.engine.phase.search_event`, same signature);
tests swap this one in (``impactpred.engine.cycle_run._SEARCH``) to compare whole runs.

Event search (:func:`first_event`): the phase ends at the first ``tau`` where one of its
event rows turns negative. It is certified, multilevel: the terms are nested by
``|lambda|``; a level resolves the slow ones on steps ``pi / (8 Lambda)`` and bounds the
others by the sum of their moduli (``|e^{lambda tau}| <= 1`` since ``Re lambda <= 0``); a
step is cleared when the cubic Hermite interpolant's minimum, less its error bound
``h^4/384 sum |b| |lambda|^4``, less that sum, stays above the rounding level. Only the
steps not cleared are searched at the next level (``_RATIO`` times finer), so the fast
modes cost work only right at an event. At the last level (every term) a sign change
brackets the root and a dip (slope from negative to positive) has its minimum located;
the root is polished by safeguarded Newton steps on the closed form, to rounding.

The uniform grids are evaluated by the exact solver's compiled
:func:`impactpred.engine.exp_kernels.sample_rows`: the exponentials advance by
``e^{lambda h}`` from point to point and are recomputed exactly every 32 points and at
the last one (values to ``~1e-15`` of the terms' moduli, far under the zero tolerance);
the certification and crossing tests run per step in
:mod:`impactpred.engine.step_kernels`.
A last-level span is evaluated in pieces, stopping at the first piece with an event.
Roots and dip minima are still located on the closed form itself (``e^{lambda tau}``
evaluated directly).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from impactpred.engine.exp_kernels import sample_rows
from impactpred.engine.phase import _poly_derivative
from impactpred.engine.search import (_ETA, _GEO, _H1, _MAX_SPLITS, _MIN_KERNEL, _RATIO,
                                      _SPLIT_SHARE, _STEP)
from impactpred.engine.step_kernels import QUIET_MIN_STEPS, crossing_steps, uncertified_steps

__all__ = ["first_event"]

#: steps of the first piece of a last-level span evaluated at once (then doubling)
_PIECE = 64


def quiet_from(lam, b, poly, tau0, tau_max, h0, zero_tol):
    """Where a span's search may stop (the compiled ``step_kernels.quiet_from``, written
    again): steps doubling from ``h0`` over ``[tau0, tau_max]``; on ``[a, e]`` each row's
    polynomial (degree <= 3; its cubic Hermite minimum, found here on a fine grid of the
    cubic itself, which is exact enough for a test oracle: the cubic's own minimum by
    its stationary points) less ``sum |b| e^{Re lambda a}``, ``zero_tol`` and rounding
    must stay positive; the end of the last step where it does not."""
    k = poly.shape[1]
    if np.any(poly[:, 4:] != 0.0) or np.any(lam.real > 0.0) or k == 0:
        return tau_max
    c = np.zeros((poly.shape[0], 4))
    c[:, :min(k, 4)] = poly[:, :4]
    amp = np.abs(b)
    last, a, h = tau0, tau0, h0
    while a < tau_max:
        e = min(a + h, tau_max)
        bound = zero_tol + amp @ np.exp(lam.real * a)
        # the cubic's minimum on [a, e]: the ends and the roots of its derivative inside
        cands = [np.full(c.shape[0], a), np.full(c.shape[0], e)]
        for r in range(c.shape[0]):
            roots = np.roots([3 * c[r, 3], 2 * c[r, 2], c[r, 1]]) if np.any(c[r, 1:]) else []
            for x in np.atleast_1d(roots):
                if abs(x.imag) < 1e-300 and a < x.real < e:
                    cand = np.full(c.shape[0], a)
                    cand[r] = x.real
                    cands.append(cand)
        low = np.min([c[:, 0] + t * (c[:, 1] + t * (c[:, 2] + t * c[:, 3])) for t in cands],
                     axis=0)
        size = np.abs(c) @ np.array([1.0, e, e * e, e ** 3])
        if not np.all(low - bound - 4 * np.finfo(float).eps * size > 0.0):
            last = e
        a, h = e, 2.0 * h
    return last


def _levels(kind, amp, scale):
    """Nested term sets for the multilevel search, slowest first.

    The first level leaves out the fastest terms whose summed moduli stay under
    ``_ETA * scale`` (every row); each further level resolves the terms up to ``_RATIO``
    times the previous level's fastest rate; the last resolves every term. Returns a
    list of ``(cols, tail, g4, h)``: the terms resolved (indices into ``kind.lam``), the
    bound ``sum |b|`` of those left out (per row), the bound ``sum |b| |lambda|^4`` of
    those resolved and the level's step ``pi / (8 Lambda)``.
    """
    order = kind.order_desc                                  # fastest first
    a = amp[:, order]
    cum = np.cumsum(a, axis=1)
    ok = (cum <= _ETA * scale[:, None]).all(axis=0)
    m = ok.size
    n_cut = int(np.argmin(ok)) if not ok.all() else m - 1
    cuts = kind.cuts.get(n_cut)
    if cuts is None:                   # depends on the rates only: cached per kind
        absd = kind.abs_lam[order]
        cuts = [n_cut]
        while cuts[-1] > 0:
            nxt = int(np.count_nonzero(absd > _RATIO * absd[cuts[-1]]))
            cuts.append(min(nxt, cuts[-1] - 1))
        kind.cuts[n_cut] = cuts
    c4 = np.cumsum((a * kind.abs_lam4[order])[:, ::-1], axis=1)[:, ::-1]
    zero = np.zeros(amp.shape[0])
    absl = kind.abs_lam
    return [(order[n_c:], cum[:, n_c - 1] if n_c else zero, c4[:, n_c],
             _STEP / absl[order[n_c]] if absl[order[n_c]] > 0 else math.inf)
            for n_c in cuts]


def first_event(kind, b, poly, tau_max, *, scale, zero_tol, on_boundary, open_rows=()):
    """First ``tau`` in ``(0, tau_max]`` where a row falls below ``-zero_tol``: the
    search of one span (:func:`_search_span`) with the phase's decaying transients
    searched apart, as the compiled :func:`impactpred.engine.search.first_event` does
    (:func:`_transient_end`, the rows restarted at its end by :func:`_shifted`).
    Arguments and result as :func:`_search_span`."""
    t0 = 0.0
    for _ in range(_MAX_SPLITS):
        cut = _transient_end(kind.lam, kind.order_desc, b, poly, tau_max - t0, scale,
                             zero_tol)
        if cut <= 0.0:
            break
        tau, row = _search_span(kind, b, poly, cut, scale=scale, zero_tol=zero_tol,
                                on_boundary=on_boundary, open_rows=open_rows)
        if tau is not None:
            return t0 + tau, row
        b, poly = _shifted(kind.lam, b, poly, cut)
        t0 += cut
        on_boundary, open_rows = False, ()
    tau, row = _search_span(kind, b, poly, tau_max - t0, scale=scale, zero_tol=zero_tol,
                            on_boundary=on_boundary, open_rows=open_rows)
    return (t0 + tau, row) if tau is not None else (None, -1)


def _transient_end(lam, order, b, poly, span, scale, zero_tol):
    """Where the decaying transient ends (s), or 0.0: the terms up to the coarsest
    level's fastest resolved one (fastest first, and any term as fast), once each is
    under the row's ``zero_tol`` (at least ``1e-15`` of its scale) shared among them, if
    before ``_SPLIT_SHARE`` of ``span`` and with every row then above twice its
    ``zero_tol``."""
    amp = np.abs(b)[:, order]
    over = (np.cumsum(amp, axis=1) > _ETA * scale[:, None]).any(axis=0)
    if not over.any():
        return 0.0
    n_fast = int(np.argmax(over)) + 1
    moduli = np.abs(lam[order])
    while n_fast < moduli.size and moduli[n_fast] == moduli[n_fast - 1]:
        n_fast += 1
    share = np.maximum(zero_tol, 1e-15 * scale)[:, None] / n_fast
    big = amp[:, :n_fast] > share
    rate = -lam[order[:n_fast]].real
    if np.any(big & (rate <= 0.0)):
        return 0.0
    with np.errstate(divide="ignore"):
        times = np.where(big, np.log(np.maximum(amp[:, :n_fast], 1e-300) / share)
                         / np.where(rate > 0, rate, 1.0), 0.0)
    cut = float(times.max())
    if not 0.0 < cut < _SPLIT_SHARE * span:
        return 0.0
    b_cut, p_cut = _shifted(lam, b, poly, cut)
    value = b_cut.real.sum(axis=1) + (p_cut[:, 0] if p_cut.shape[1] else 0.0)
    return cut if np.all(value > 2.0 * zero_tol) else 0.0


def _shifted(lam, b, poly, t):
    """Rows restarted at ``tau = t``: ``b e^{lambda t}`` and the polynomial's Taylor
    coefficients there."""
    k = poly.shape[1]
    shift = np.array([[math.comb(c, q) * t ** (c - q) if c >= q else 0.0
                       for q in range(k)] for c in range(k)])
    return b * np.exp(lam * t), poly @ shift if k else poly.copy()


def _search_span(kind, b, poly, tau_max, *, scale, zero_tol, on_boundary, open_rows=()):
    """First ``tau`` in ``(0, tau_max]`` where a row falls below ``-zero_tol``.

    Certified multilevel search: the terms ``b_j e^{lambda_j tau}`` are nested by
    ``|lambda_j|`` into levels ``Lambda_0 < Lambda_1 < ... `` (ratio ~ ``_RATIO``); level
    ``l`` resolves the terms with ``|lambda| <= Lambda_l`` on steps ``h_l = pi / (8
    Lambda_l)`` and bounds the rest by ``A_l = sum |b_j|`` (``|e^{lambda tau}| <= 1``,
    ``Re lambda <= 0``). On a step, the exact minimum of the cubic Hermite interpolant of
    the resolved part, less its error bound ``h^4 / 384 sum |b_j| |lambda_j|^4``, less
    ``A_l``, certifies that no row can cross; only uncertified steps are searched at the
    next level, and at the last one (every term) a sign change brackets the root and a
    dip (slope from negative to positive) has its minimum located; the root is polished
    by safeguarded Newton steps on the closed form. The polynomial part (degree <= 3)
    is interpolated exactly.

    Parameters
    ----------
    kind : PhaseKind
        Gives the exponents ``lam`` (m,).
    b : ndarray of complex, shape (K, m); poly : ndarray, shape (K, deg <= 4)
        Rows ``Re(b e^{lam tau}) + poly(tau)``.
    tau_max : float
        End of the search (s).
    scale, zero_tol : ndarray, shape (K,)
        Each row's scale (the terms bounded, not sampled, on the first level carry at
        most ``_ETA`` of it) and rounding level.
    on_boundary : bool
        The phase starts at an event: a row (not in ``open_rows``) starting at
        ``<= zero_tol`` that does not turn positive on a geometric grid of the first
        fine step ends the phase at once (``tau = 0``). On that grid, crossings and
        dips between its points are searched as at the last level.
    open_rows : sequence of int
        Rows that start at 0 and were decided to open (the contact decision of
        :mod:`impactpred.engine.cycle_run`): never an event at ``tau = 0``; if rounding keeps them
        negative, their event is where they leave ``[-zero_tol, 0]``.

    Returns
    -------
    (tau, row) or (None, -1) when no row crosses before ``tau_max``.
    """
    lam = kind.lam
    K = b.shape[0]
    amp = np.abs(b)
    total = amp.sum(axis=1) + np.abs(poly).sum(axis=1)
    levels = _levels(kind, amp, scale) if lam.size else []
    h_f = levels[-1][3] if levels else tau_max
    bl = b * lam
    k = poly.shape[1]
    dpoly = _poly_derivative(poly)
    PP = np.vstack([poly, dpoly]) if k else None
    ar = np.arange(k)
    BB = np.vstack([b, bl])
    PP_k = PP if k else np.zeros((2 * K, 0))
    opened = np.zeros(K, bool)
    opened[list(open_rows)] = True
    n_lev = len(levels)
    level_b = {}

    def ev(taus, lv=None, h=None):
        """Values and slopes (2K x len(taus)) of all terms, or of level ``lv``'s.

        ``h``: ``taus`` is uniform with that step (but its last point): compiled
        recurrence (:func:`impactpred.engine.exp_kernels.sample_rows`).
        """
        if h is not None and taus.size >= _MIN_KERNEL:
            if lv is None or lv == n_lev - 1:
                lam_l, B = lam, BB
            else:
                if lv not in level_b:
                    c = levels[lv][0]
                    level_b[lv] = (lam[c], BB[:, c])
                lam_l, B = level_b[lv]
            return sample_rows(lam_l, B, PP_k, taus, h)
        if lv is None or lv == n_lev - 1:
            out = (BB @ np.exp(np.outer(lam, taus))).real
        else:
            if lv not in level_b:
                c = levels[lv][0]
                level_b[lv] = (lam[c], BB[:, c])
            lam_l, B = level_b[lv]
            out = (B @ np.exp(np.outer(lam_l, taus))).real
        out = np.ascontiguousarray(out)
        if k:
            out += PP @ (taus[None, :] ** ar[:, None])
        return out

    def row_fun(i, d=0):
        bi = b[i] if d == 0 else bl[i]
        pi = (poly[i] if d == 0 else dpoly[i])[::-1].tolist()

        def f(tau):
            value = float(np.dot(bi, np.exp(lam * tau)).real)
            acc = 0.0
            for c in pi:
                acc = acc * tau + c
            return value + acc
        return f

    def locate(i, lo, hi):
        """Root of row ``i`` in ``[lo, hi]`` (>= -zero_tol at lo, < -zero_tol at hi).

        Newton's method on the closed form, safeguarded by bisection of the bracket. An
        open row still at rounding level at ``lo`` (value in ``[-zero_tol, 0]``) has its
        event where it leaves that band (root of ``row + zero_tol``).
        """
        bi, bli = b[i], bl[i]
        p0, p1 = poly[i][::-1].tolist(), dpoly[i][::-1].tolist()

        def fd(tau):
            ex = np.exp(lam * tau)
            v, d = float(np.dot(bi, ex).real), float(np.dot(bli, ex).real)
            a0 = 0.0
            for c in p0:
                a0 = a0 * tau + c
            a1 = 0.0
            for c in p1:
                a1 = a1 * tau + c
            return v + a0 + shift, d + a1

        shift = 0.0
        noise = 4e-16 * total[i]
        f_lo, _ = fd(lo)
        if f_lo <= 0.0:
            if not (opened[i] and f_lo >= -zero_tol[i]):
                return lo
            # an open row may rise above rounding by less than zero_tol (a low bounce):
            # its event is then its own root after that lobe, found on a geometric grid
            # from the phase's start (where the open row is 0)
            g = hi * _GEO
            vals = [fd(x)[0] for x in g]
            pos = [j for j, v in enumerate(vals) if v > noise]
            neg = [j for j, v in enumerate(vals) if pos and j > pos[0] and v <= 0.0]
            if neg:
                lo, hi = g[neg[0] - 1], g[neg[0]]
                f_lo = vals[neg[0] - 1]
            else:
                shift = float(zero_tol[i])
                f_lo += shift
                if f_lo <= 0.0:
                    return lo
        f_hi, _ = fd(hi)
        x = lo + (hi - lo) * f_lo / (f_lo - f_hi)
        for _ in range(100):
            fx, dx = fd(x)
            if abs(fx) <= noise:
                return x
            if fx > 0.0:
                lo = x
            elif fx < 0.0:
                hi = x
            else:
                return x
            x_new = x - fx / dx if dx != 0.0 else 0.5 * (lo + hi)
            if not lo < x_new < hi:
                x_new = 0.5 * (lo + hi)
            if abs(x_new - x) <= 4e-16 * max(abs(x), 1e-300) or hi - lo <= 4e-16 * hi:
                return x_new
            x = x_new
        return x

    def crossings(t_all, v, g4):
        """First event among steps ``t_all[j] -> t_all[j+1]`` with full values, or None.

        ``v`` (2K x len(t_all)): values and slopes. The steps flagged by
        :func:`impactpred.engine.step_kernels.crossing_steps` (a row below ``-zero_tol`` at
        the step's end,
        or a dip whose interpolated minimum may reach it) are examined in order.
        """
        steps, code = crossing_steps(t_all, v, K, g4, zero_tol)
        for idx, j in enumerate(steps.tolist()):
            best = None
            for i in range(K):
                c = code[i, idx]
                if c == 0:
                    continue
                lo, hi = t_all[j], t_all[j + 1]
                if c == 2:
                    rate = row_fun(i, 1)
                    d_lo, d_hi = rate(lo), rate(hi)
                    t_min = (lo if d_lo >= 0.0 else hi if d_hi <= 0.0
                             else brentq(rate, lo, hi, xtol=4e-16 * hi))
                    if row_fun(i)(t_min) >= -zero_tol[i]:
                        continue
                    hi = t_min
                root = locate(i, lo, hi)
                if best is None or root < best[0]:
                    best = (root, int(i))
            if best is not None:
                return best
        return None

    g4_full = amp @ kind.abs_lam4

    def fine(a, b_end):
        """Search ``[a, b_end]`` with every term, every ``h_f`` at most.

        The grid is evaluated in pieces (``_PIECE`` steps, doubling), stopping at the
        first piece with an event: a span is often uncertified only because a row is
        negative after its first crossing, up to the span's end.
        """
        n = max(1, int(math.ceil((b_end - a) / h_f - 1e-9)))
        t_all = a + (b_end - a) * np.arange(n + 1) / n
        t_all[-1] = b_end
        h = (b_end - a) / n
        i0, piece = 0, _PIECE
        while i0 < n:
            i1 = min(n, i0 + piece)
            tt = t_all[i0:i1 + 1]
            found = crossings(tt, ev(tt, h=h), g4_full)
            if found is not None:
                return found
            i0, piece = i1, min(2 * piece, 16 * _PIECE)
        return None

    def uncertified(lv, t_all, v):
        """Indices of the steps of ``t_all`` that level ``lv`` cannot certify.

        Lower bound of the cubic Hermite interpolant ``H00 s_a + H01 s_b + h H10 s'_a +
        h H11 s'_b`` (``H00 + H01 = 1``, both >= 0; ``0 <= H10 <= 4/27``,
        ``-4/27 <= H11 <= 0``), less its error bound, less the terms left out; the exact
        minimum of the interpolant where that cheap bound fails
        (:func:`impactpred.engine.step_kernels.uncertified_steps`).
        """
        _, tail, g4, _ = levels[lv]
        return uncertified_steps(t_all, v, K, g4, tail, zero_tol, _H1)

    def refine(lv, a, b_end):
        """First event in ``[a, b_end]``, searching level ``lv`` and deeper."""
        if lv >= n_lev - 1:
            return fine(a, b_end)
        h = levels[lv][3]
        n = max(1, int(math.ceil((b_end - a) / h - 1e-9)))
        t_all = a + (b_end - a) * np.arange(n + 1) / n
        t_all[-1] = b_end
        for j0, j1 in _runs(uncertified(lv, t_all, ev(t_all, lv, (b_end - a) / n))):
            found = refine(lv + 1, t_all[j0], t_all[j1 + 1])
            if found is not None:
                return found
        return None

    tau = 0.0
    if on_boundary:     # a start lobe shorter than a fine step is seen on this grid
        geo = min(h_f, tau_max) * _GEO
        taus = np.concatenate([[0.0], geo])
        e_all = ev(taus)
        e = e_all[:K]
        eg = e[:, 1:]
        for i in np.flatnonzero((e[:, 0] <= zero_tol) & ~opened):  # rows at an event
            pos = np.flatnonzero(eg[i] > zero_tol[i])
            if pos.size == 0 or e[i, 0] < -zero_tol[i] or np.any(eg[i, :pos[0]] < -zero_tol[i]):
                return 0.0, int(i)     # the row does not open: the event is now
            eg[i, :pos[0]] = zero_tol[i]   # rounding-level start: not an event
        # sign changes on the grid, and dips between its points (a row that starts
        # positive may cross and return inside one geometric step)
        found = crossings(taus, e_all, g4_full)
        if found is not None:
            return found
        if geo[-1] >= tau_max:
            return None, -1
        # the rows opened: search on from the end of the geometric grid
        tau = float(geo[-1])
    if n_lev == 0:          # constant rows (no live term): only the polynomial
        found = fine(tau, tau_max)
        return found if found is not None else (None, -1)
    h0 = levels[0][3]
    if tau_max - tau > QUIET_MIN_STEPS * h0:     # a long span: its quiet tail cut off
        tau_max = quiet_from(lam, b, poly, tau, tau_max, h0, zero_tol)
        if tau_max <= tau:
            return None, -1
    chunk = 16
    while tau < tau_max:
        grid = tau + h0 * np.arange(0, chunk + 1)
        if grid[-1] >= tau_max:
            grid = np.append(grid[grid < tau_max], tau_max)
        for j0, j1 in _runs(uncertified(0, grid, ev(grid, 0, h0))):
            # consecutive uncertified steps are searched as one span (same first event)
            found = (refine(1, grid[j0], grid[j1 + 1]) if n_lev > 1
                     else fine(grid[j0], grid[j1 + 1]))
            if found is not None:
                return found
        tau = float(grid[-1])
        chunk = min(2 * chunk, 512)
    return None, -1


def _runs(indices):
    """Runs of consecutive step indices as ``(first, last)`` pairs, in order."""
    out = []
    for i in indices.tolist():
        if out and i == out[-1][1] + 1:
            out[-1][1] = i
        else:
            out.append([i, i])
    return [(a, b) for a, b in out]
