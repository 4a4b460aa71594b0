"""Compiled kernels (numba) of the certified event search: per-step certification.

The rows searched by :func:`.search.first_event` are sums of exponentials

    r(tau) = Re(sum_j B_j e^{lambda_j tau}) + sum_c P_c tau^c      (tau in s)

(values and slopes: a slope row is the value row with ``B_j lambda_j`` and the
polynomial's derivative). They are evaluated on uniform grids by the exact solver's
:func:`impactpred.engine.exp_kernels.sample_rows` (the exponentials advance by
``e^{lambda h}``, recomputed directly every 32 points and at the last one: an absolute
error of a few ``1e-15`` of the terms' moduli, far under the search's zero tolerance,
``1e-12`` of them). This module holds the per-step tests of the certified search, with
the Hermite minimum :func:`cubic_min` (the exact solver's ``hermite_min``).

Compiled on first use (``cache=True``: loaded from numba's cache afterwards); nothing
runs at import beyond the definitions.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

# the grid evaluation and the Hermite minimum are the exact solver's (one implementation)
from .exp_kernels import hermite_min as cubic_min

__all__ = ["crossing_steps", "cubic_min", "quiet_from", "uncertified_steps"]


@njit(cache=True)
def uncertified_steps(t_all, v, K, g4, tail, zero_tol, h1):  # pragma: no cover - compiled
    """Steps ``t_all[j] -> t_all[j + 1]`` a search level cannot certify (indices, in order).

    ``v`` (2K x n): the level's values (rows ``:K``) and slopes (rows ``K:``) on
    ``t_all`` (s). A step is certified when, for every row, the cubic Hermite
    interpolant's minimum, less its error bound ``h^4 / 384 g4``, less ``tail`` (the
    terms left out) and ``zero_tol``, stays positive; the cheap bound ``min(s_a, s_b) -
    h1 h (max(-s'_a, 0) + max(s'_b, 0))`` (``h1 = 4/27``) is tried first, the exact
    minimum (:func:`cubic_min`) only where it fails.
    """
    n = t_all.size - 1
    out = np.empty(n, np.int64)
    cnt = 0
    for j in range(n):
        h = t_all[j + 1] - t_all[j]
        e4 = h ** 4 / 384.0
        cheap = False
        for r in range(K):
            sa, sb, da, db = v[r, j], v[r, j + 1], v[K + r, j], v[K + r, j + 1]
            b = (min(sa, sb) - h1 * h * (max(-da, 0.0) + max(db, 0.0))
                 - e4 * g4[r] - tail[r] - zero_tol[r])
            if b <= 0.0:
                cheap = True
                break
        if not cheap:
            continue
        for r in range(K):
            cm = cubic_min(v[r, j], v[r, j + 1], v[K + r, j], v[K + r, j + 1], h)
            if cm - (e4 * g4[r] + tail[r] + zero_tol[r]) <= 0.0:
                out[cnt] = j
                cnt += 1
                break
    return out[:cnt]


@njit(cache=True)
def crossing_steps(t_all, v, K, g4, zero_tol):  # pragma: no cover - compiled
    """Steps where a row may cross ``-zero_tol`` (every term resolved), in order.

    ``v`` (2K x n): values and slopes on ``t_all`` (s). Returns ``(steps, code)``:
    ``code[r, i]`` is 1 when row ``r`` is below ``-zero_tol`` at the end of step
    ``steps[i]``, 2 when it has a dip there (slope from negative to positive) whose
    interpolated minimum, less the error bound ``h^4 / 384 g4``, is under
    ``zero_tol``, else 0.
    """
    n = t_all.size - 1
    steps = np.empty(n, np.int64)
    code = np.zeros((K, n), np.int8)
    cnt = 0
    for j in range(n):
        h = t_all[j + 1] - t_all[j]
        hit = False
        for r in range(K):
            if v[r, j + 1] < -zero_tol[r]:
                code[r, cnt] = 1
                hit = True
            elif v[K + r, j] < 0.0 and v[K + r, j + 1] > 0.0:
                cm = cubic_min(v[r, j], v[r, j + 1], v[K + r, j], v[K + r, j + 1], h)
                if cm - h ** 4 / 384.0 * g4[r] < zero_tol[r]:
                    code[r, cnt] = 2
                    hit = True
        if hit:
            steps[cnt] = j
            cnt += 1
    return steps[:cnt], code[:, :cnt]


#: a span searched at the coarsest level in more steps than this first has its quiet
#: tail cut off by :func:`quiet_from` (one to a few dozen polynomial evaluations)
QUIET_MIN_STEPS = 1024.0


@njit(cache=True)
def quiet_from(lam, b, poly, tau0, tau_max, h0, zero_tol):  # pragma: no cover - compiled
    """Where a span's search may stop: after it the rows certainly stay above ``-zero_tol``.

    The span ``[tau0, tau_max]`` (s) is cut into steps doubling from ``h0`` (s); on a step
    ``[a, e]`` each row's polynomial part (degree <= 3: its cubic Hermite minimum is
    exact) less the terms' bound ``sum_j |b_j| e^{Re lambda_j a}`` (``Re lambda <= 0``),
    less ``zero_tol`` and the polynomial's rounding, must stay positive. Returns the end
    of the last step where it does not (``tau0``: every step certified, no event), or
    ``tau_max`` where this test does not apply (no polynomial, one of degree over 3, or
    a growing term, ``Re lambda > 0``: a model given with ``check_passive=False``). A
    receding body's free flight, its vibration decayed or small beside its gap, is then
    cleared in ``log2`` of its span in steps, not in steps of its slowest vibration (a
    damped spring-mass left behind at 1e6 s: 17 s of search before). The steps are checked
    from the last back, so a span whose tail is not quiet costs one step's O(rows x
    terms) work (the impact damper's forced phases).
    """
    K, m = b.shape
    k = poly.shape[1]
    for r in range(K):
        for c in range(4, k):           # the rows' degree, not the block's: at most 3
            if poly[r, c] != 0.0:
                return tau_max
    k = min(k, 4)
    for j in range(m):
        if lam[j].real > 0.0:           # a growing term: no decaying bound
            return tau_max
    if k == 0:
        return tau_max
    amp = np.empty((K, m))
    for r in range(K):
        for j in range(m):
            amp[r, j] = math.sqrt(b[r, j].real ** 2 + b[r, j].imag ** 2)
    eps4 = 4.0 * np.finfo(np.float64).eps
    # the steps' ends, then checked from the last back: the first that fails ends the
    # search (where the tail is not quiet, after one step's work)
    n_steps = 1
    h = h0
    while tau0 + h < tau_max:
        n_steps += 1
        h *= 2.0
    ends = np.empty(n_steps + 1)
    ends[0] = tau0
    h = h0
    for q in range(1, n_steps + 1):
        ends[q] = min(ends[q - 1] + h, tau_max)
        h *= 2.0
    decay = np.empty(m)
    for q in range(n_steps - 1, -1, -1):
        a, e = ends[q], ends[q + 1]
        step = e - a
        for j in range(m):
            decay[j] = math.exp(lam[j].real * a)
        for r in range(K):
            bound = zero_tol[r]
            for j in range(m):
                bound += amp[r, j] * decay[j]
            pa, da, pe, de, size = poly[r, 0], 0.0, poly[r, 0], 0.0, abs(poly[r, 0])
            wa, we = 1.0, 1.0                    # a^(c-1), e^(c-1)
            for c in range(1, k):
                coef = poly[r, c]
                da += c * coef * wa
                de += c * coef * we
                wa *= a
                we *= e
                pa += coef * wa
                pe += coef * we
                size += abs(coef) * abs(we)
            if not cubic_min(pa, pe, da, de, step) - bound - eps4 * size > 0.0:   # NaN too
                return e
    return tau0
