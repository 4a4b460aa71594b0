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

import numpy as np
from numba import njit

# the grid evaluation and the Hermite minimum are the exact solver's (one implementation)
from .exp_kernels import hermite_min as cubic_min

__all__ = ["crossing_steps", "cubic_min", "uncertified_steps"]


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
