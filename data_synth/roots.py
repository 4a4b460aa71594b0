"""Roots of the cantilever frequency equation ``1 + cosh(e) cos(e) = 0`` and their power sums.

Dividing by ``cosh e`` gives the stable form ``g(e) = cos(e) + 1/cosh(e) = 0``. Near
``x_k = (k - 1/2) pi``, ``cos(x_k + d) = (-1)^k sin(d)`` and ``1/cosh(e) ~ 2 exp(-e)``, so

    eps_k = x_k + (-1)^(k+1) 2 exp(-x_k) + O(exp(-2 x_k)),

where the asymptotic form overshoots by ``4 exp(-2 x_k) (1 + O(exp(-x_k)))`` (less than
``4.2 exp(-2 x_k)`` for ``k >= 2``); for ``k >= 8`` (``x_k > 23``) that is below a
thousandth of an ulp of ``x_k`` and the asymptotic form is exact in double precision (for
``k >= 13`` the correction itself is below half an ulp).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.special import polygamma

from modalid.validation import as_count

__all__ = ["cantilever_roots"]

# Roots k <= _N_NEWTON are refined by Newton's method; the rest use the asymptotic form.
_N_NEWTON = 12
# Beyond this index eps_k = (k - 1/2) pi to far below rounding (|d_k| < 1e-26).
_N_EXACT_TAIL = 20


def _asymptotic(k: np.ndarray) -> np.ndarray:
    """``x_k + (-1)^(k+1) 2 exp(-x_k)``, ``x_k = (k - 1/2) pi``, for ``k = 1, 2, ..., n``
    (a float array starting at 1).

    The correction is below half an ulp of ``x_k`` for ``k >= 13``; it is added only for
    ``k <= 40`` (the sum is unchanged beyond).
    """
    x = (k - 0.5) * np.pi
    head = k[:40]
    sign = np.where(np.mod(head, 2.0) == 1.0, 1.0, -1.0)
    x[:40] += sign * 2.0 * np.exp(-x[:40])
    return x


def cantilever_roots(n) -> np.ndarray:
    """First ``n`` positive roots ``eps_k`` of ``1 + cosh(e) cos(e) = 0``.

    Parameters
    ----------
    n : int
        Number of roots, >= 0.

    Returns
    -------
    ndarray of float, shape (n,)
        ``eps_1 = 1.8751040687...``, ``eps_2 = 4.6940911329...``, increasing; to machine
        precision for every ``k``.

    Notes
    -----
    The first 12 roots: vectorised Newton iterations on ``cos(e) + 1/cosh(e) = 0`` started
    from the asymptotic form (8 iterations; 5 reach rounding). All others:
    ``(k - 1/2) pi + (-1)^(k+1) 2 exp(-(k - 1/2) pi)``, whose error, about
    ``4 exp(-(2k - 1) pi)``, is far below rounding there. ``n = 10**6`` takes a few
    milliseconds.
    """
    n = as_count("n", n)
    k = np.arange(1.0, n + 1.0)
    roots = _asymptotic(k)
    m = min(n, _N_NEWTON)
    if m:
        e = roots[:m]
        # From the asymptotic start the error of eps_1 is 0.11; quadratic convergence
        # reaches rounding after 5 steps; 8 are taken.
        for _ in range(8):
            sech = 1.0 / np.cosh(e)
            e = e - (np.cos(e) + sech) / (-np.sin(e) - sech * np.tanh(e))
        roots[:m] = e
    return roots


def _power_tail(n: int, power: int) -> float:
    """``sum_{k > n} eps_k^(-power)`` for ``power >= 2``, to rounding.

    Exact roots up to ``max(n, 20)``; beyond, ``eps_k = (k - 1/2) pi`` (to within
    ``1e-26`` relative) and the sum is a polygamma value:
    ``sum_{k > N} ((k - 1/2) pi)^(-p) = psi^(p-1)(N + 1/2) / ((p-1)! pi^p)``.
    """
    top = max(n, _N_EXACT_TAIL)
    tail = float(polygamma(power - 1, top + 0.5)) / (math.factorial(power - 1) * math.pi**power)
    if n >= top:
        return tail
    head = cantilever_roots(top)[n:]
    return float(np.sum(head[::-1] ** (-float(power)))) + tail  # small terms first


def _terms_for_tail(power: int, bound: float) -> int:
    """Smallest ``n >= 0`` with ``sum_{k > n} eps_k^(-power) <= bound`` (``bound > 0``).

    The tail decreases with ``n``: bisection between 0 and an upper bound from the
    asymptotic tail ``~ 1/((p-1) pi^p n^(p-1))``.
    """
    hi = int(2.0 * (1.0 / ((power - 1) * math.pi**power * bound)) ** (1.0 / (power - 1))) + 2
    while _power_tail(hi, power) > bound:
        hi *= 2
    lo = -1  # tail(lo) > bound is assumed for lo = -1 (an empty head)
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if mid >= 0 and _power_tail(mid, power) <= bound:
            hi = mid
        else:
            lo = mid
    return hi
