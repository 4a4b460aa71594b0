"""Cantilever responses away from the tip: transfer receptance, mode shapes, modal series.

Coordinates: ``xi`` = distance from the struck tip as a fraction of the length (``xi = 1``
the clamp), ``u = 1 - xi``; ``K = EI/l^3``, ``T = sqrt(m/K)``, ``e^4 = -s^2 T^2``. The
deflection ``W(xi)`` per unit tip force, in units of ``1/K``, solves ``W'''' = e^4 W`` with
``W''(0) = 0``, ``W'''(0) = 1`` (free tip, unit shear) and ``W(1) = W'(1) = 0`` (clamp):

    K H(xi, s) = N(xi) / (2 e^3 (1 + cosh e cos e)),
    N(xi) = (cosh e sin e - sinh e cos e)(cosh e xi + cos e xi)
          - (1 + cos e cosh e + sin e sinh e)(sinh e xi + sin e xi)
          + 2 (1 + cosh e cos e) sinh e xi,

which is the tip receptance of :mod:`data_synth.beam` at ``xi = 0``, vanishes with its
slope at ``xi = 1`` and has the static limit ``(1 - xi)^2 (2 + xi)/6`` (the
Euler-Bernoulli deflection under a tip load).
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from ._transfer import _safe_ratio

__all__ = []


# ------------------------------------------- shared with the tip receptance (beam.py)
# 1 + cosh e cos e = 2 + sum_{j>=1} (-4)^j z^j/(4j)!, z = e^4 (entire)
_DEN_SERIES = np.array([2.0] + [(-4.0) ** j / math.factorial(4 * j) for j in range(1, 9)])


def _horner(coefficients: np.ndarray, z: np.ndarray) -> np.ndarray:
    out = np.zeros_like(z)
    for c in coefficients[::-1]:
        out = out * z + c
    return out


def _folded_branch(x: np.ndarray, small: np.ndarray):
    """The bounded exponentials of the beam's closed forms at ``|x| >= 1``.

    ``e = sqrt(i x)`` (``x`` replaced by 1 where ``small``) rotated by a power of ``i``
    into ``Re e >= |Im e|`` and conjugated into ``Im e >= 0`` where ``lower``; returns
    ``(e, lower, P, Q, G + (1+P)(1+Q))`` with ``P = exp(-2e)``, ``Q = exp(2ie)``,
    ``G = 4 exp(-(1 - i) e)``, all of modulus <= 4. The caller conjugates its result
    back where ``lower``.
    """
    e = np.sqrt(1j * np.where(small, 1.0, x))
    angle = np.angle(e)
    e = np.where(angle > 0.25 * np.pi, -1j * e, np.where(angle < -0.25 * np.pi, 1j * e, e))
    lower = e.imag < 0.0
    e = np.where(lower, e.conj(), e)
    with np.errstate(under="ignore", over="ignore", invalid="ignore"):
        p = np.exp(-2.0 * e)
        q = np.exp(2j * e)
        denominator = 4.0 * np.exp(-(1.0 - 1j) * e) + (1.0 + p) * (1.0 + q)
    return e, lower, p, q, denominator


# ---------------------------------------------------------- small |e|: Taylor series
def _polynomial_series(n_terms: int) -> list[list[Fraction]]:
    """Exact polynomials ``P_j(u)`` (coefficients of ``u^0, u^1, ...``) with
    ``W = sum_j e^(4j) P_j(u)``, ``u = 1 - xi``.

    ``P_j'''' = P_(j-1)`` (derivatives in ``u``; ``P_(-1) = 0``), ``P_j(0) = P_j'(0) = 0``
    (clamp), ``P_j''(1) = 0`` and ``P_j'''(1) = -[j = 0]`` (free tip, unit shear):
    integrate four times from ``u = 0`` and add ``c_2 u^2 + c_3 u^3``.
    ``P_0 = u^2 (3 - u) / 6``.
    """
    def integrate(p):
        return [Fraction(0)] + [c / (i + 1) for i, c in enumerate(p)]

    def derivative_at_one(p, order):
        return sum(c * math.perm(i, order) for i, c in enumerate(p) if i >= order)

    out, prev = [], None
    for j in range(n_terms):
        q = [Fraction(0)] * 4
        if prev is not None:
            q = integrate(integrate(integrate(integrate(prev))))
        c3 = (-(1 if j == 0 else 0) - derivative_at_one(q, 3)) / 6
        c2 = -(derivative_at_one(q, 2) + 6 * c3) / 2
        q[2] += c2
        q[3] += c3
        out.append(q)
        prev = q
    return out


def _numerator_series(n_terms: int) -> np.ndarray:
    """Coefficients ``c[j, i]`` of ``K H (1 + cosh e cos e) = sum_j z^j sum_i c[j, i] u^i``,
    ``z = e^4`` (an entire function of ``z``; ``c[j, .]`` falls like ``1/(4j)!``).

    At ``u = 1`` (the tip) the row sums are ``4 (-4)^j/(4j + 3)!``, the numerator series of
    :mod:`data_synth.beam`.
    """
    polys = _polynomial_series(n_terms)
    den = [Fraction(2)] + [Fraction((-4) ** j, math.factorial(4 * j))
                           for j in range(1, n_terms)]
    width = max(len(p) for p in polys)
    out = np.zeros((n_terms, width))
    for j in range(n_terms):
        acc = [Fraction(0)] * width
        for i in range(j + 1):
            for k, c in enumerate(polys[i]):
                acc[k] += c * den[j - i]
        out[j] = [float(c) for c in acc]
    return out


# |z| < 1: the j = 8 row is below 1e-30; 9 rows as the driving-point series.
_NUM_XI_SERIES = _numerator_series(9)

# ------------------------------------------------------ large |e|: bounded exponentials
# N(xi) exp(-(1 - i) e) = (1/4) sum c exp(e (a0 + a1 xi) + i e (b0 + b1 xi)): each row is
# (a0, a1, b0, b1, c). With Re e >= Im e >= 0 every exponent has a non-positive real part
# (a <= 0 and a <= b for xi in [0, 1]), so every term is bounded by 1.
_EXP_TERMS = (
    (-2, 0, 0, 1, 1 + 1j), (-2, 0, 2, -1, 1 - 1j), (-2, 1, 0, 0, 1 + 1j),
    (-2, 1, 2, 0, 1 - 1j), (-1, -1, 1, 0, -2), (-1, 0, 1, -1, -2j), (-1, 0, 1, 1, 2j),
    (-1, 1, 1, 0, 2), (0, -1, 0, 0, -1 + 1j), (0, -1, 2, 0, -1 - 1j), (0, 0, 0, 1, -1 + 1j),
    (0, 0, 2, -1, -1 - 1j),
)


def _transfer(x: np.ndarray, xi: np.ndarray, flex: float) -> np.ndarray:
    """``H(xi, s)`` as a function of ``x = sT`` (complex, any shape), ``flex = 1/K`` (m/N);
    shape ``xi.shape + x.shape``. No overflow, no cancellation near ``s = 0``, never ``nan``.

    ``|x| < 1``: ``sum_j z^j C_j(u) / (1 + cosh e cos e)`` with ``z = -x^2`` (both series,
    :data:`_NUM_XI_SERIES` and the driving point's denominator). Otherwise the branch of
    ``e = sqrt(i x)`` with ``Re e >= Im e >= 0`` (``H`` depends on ``e^4`` only and is real
    on the real axis, so a power of ``i`` and a conjugation bring ``e`` there) and::

        K H = 2 N(xi) exp(-(1-i)e) / (e^3 [G + (1+P)(1+Q)])

    with ``P = exp(-2e)``, ``Q = exp(2ie)``, ``G = 4 exp(-(1-i)e)`` and the numerator
    written as 12 bounded exponentials (:data:`_EXP_TERMS`). The absolute error is a few
    ulps of ``|H(0, s)|``; the relative accuracy degrades only next to the clamp, where
    ``H`` vanishes.
    """
    pad = (1,) * x.ndim
    xi_b = xi.reshape(xi.shape + pad)
    u = 1.0 - xi_b
    small = np.abs(x) < 1.0
    z = -np.where(small, x, 0.0) ** 2
    num = np.zeros(xi.shape + x.shape, dtype=complex)
    for row in _NUM_XI_SERIES[::-1]:
        num = num * z + np.polynomial.polynomial.polyval(u, row)
    series = flex * num / _horner(_DEN_SERIES, z)

    e, lower, _, _, denominator = _folded_branch(x, small)
    with np.errstate(under="ignore", over="ignore", invalid="ignore"):
        numerator = np.zeros(xi.shape + x.shape, dtype=complex)
        for a0, a1, b0, b1, c in _EXP_TERMS:
            numerator = numerator + c * np.exp(e * (a0 + a1 * xi_b) + 1j * e * (b0 + b1 * xi_b))
        r3 = (1.0 / e) ** 3  # |e| >= 1; underflows (to 0) where e**3 would overflow
        direct = _safe_ratio(0.5 * flex * numerator * r3, denominator)
    direct = np.where(lower, direct.conj(), direct)
    return np.where(small, series, direct)


# ------------------------------------------------------------------ mode shapes
def _shape_ratios(roots: np.ndarray, xi: np.ndarray) -> np.ndarray:
    """``phi_k(xi) / phi_k(0)`` for roots ``beta_k`` (shape (n,)), shape (n_points, n).

    From the clamp, ``x = 1 - xi``, the classical shape is
    ``Y(x) = cosh bx - cos bx - sigma (sinh bx - sin bx)``,
    ``sigma = (cosh b + cos b)/(sinh b + sin b)``; with ``d = 1 - exp(-2b) + 2 exp(-b) sin b``
    (so ``sinh b + sin b = exp(b) d / 2``) the stable form, every term bounded, is::

        Y(x) = (1 + sigma)/2 exp(-bx) + (sin b - cos b - exp(-b)) exp(-b(1 - x)) / d
               - cos bx + sigma sin bx,
        sigma = (1 + exp(-2b) + 2 exp(-b) cos b) / d.

    (The naive form loses ``log10(cosh b)`` digits: all of them beyond ~14 modes.) The
    ratio to the computed tip value ``Y(1) = 2 (-1)^(k+1)`` (to rounding) is returned, so
    it is exactly 1 at ``xi = 0``; ``|ratio| <= 1`` everywhere (the tip moves most).
    """
    b = roots[None, :]
    em = np.exp(-b)
    sb, cb = np.sin(b), np.cos(b)
    d = 1.0 - em * em + 2.0 * em * sb
    sigma = (1.0 + em * em + 2.0 * em * cb) / d
    near = (sb - cb - em) / d

    def shape(x):
        bx = x[:, None] * b
        with np.errstate(under="ignore"):
            return (0.5 * (1.0 + sigma) * np.exp(-bx) + near * np.exp(-(b - bx))
                    - np.cos(bx) + sigma * np.sin(bx))

    return shape(1.0 - xi) / shape(np.ones(1))


# ------------------------------------------------------------------ modal series
def _weighted_series(tau: np.ndarray, freq: np.ndarray, weights: np.ndarray, kind: str,
                     block: int) -> np.ndarray:
    """``sum_k weights[p, k] f(freq_k tau)`` for every point ``p``, shape ``(n_points, tau.size)``.

    ``kind="impulse"``: ``f = sin``; ``"step"``: ``f = 2 sin^2(./2)``. Phases in turns,
    reduced to ``[-1/2, 1/2]`` before the sine; blocks of at most ``block`` (time x mode)
    elements; the last modes (smallest terms) first.
    """
    n_points, n = weights.shape
    out = np.zeros((n_points, tau.size))
    if n == 0 or tau.size == 0:
        return out
    turns = freq / (2.0 * np.pi)
    t_block = min(tau.size, block)
    k_block = max(1, block // t_block)
    for i in range(0, tau.size, t_block):
        ti = tau[i:i + t_block]
        acc = np.zeros((n_points, ti.size))
        for j in reversed(range(0, n, k_block)):
            ph = np.multiply.outer(ti, turns[j:j + k_block])
            ph -= np.rint(ph)
            f = np.sin(2.0 * np.pi * ph) if kind == "impulse" else 2.0 * np.sin(np.pi * ph) ** 2
            acc += weights[:, j:j + k_block] @ f.T
        out[:, i:i + t_block] = acc
    return out
