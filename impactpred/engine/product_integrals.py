"""Exact integrals of products of a linear phase's outputs over its runs.

The exact solver's energy bookkeeping needs ``int_0^h a(t) b(t) dt`` for output rows ``a``,
``b`` of a phase (the contact force and a contact point's velocity) over every run of the
phase. On a phase's spectral form (:class:`impactpred.engine.spectral.SpectralPhase`) each
row is a polynomial of degree ``< k`` plus ``Re sum_j c_j e^(l_j t)`` (conjugate pairs
folded), so the integrals have closed forms. Per run of length ``h``, the rates split into
slow ones (``|l| h <=`` :data:`TAYLOR_RADIUS`) and fast ones:

* the polynomial and the slow exponentials: their Taylor series to :data:`TAYLOR_TERMS`
  terms, whose products integrate to ``h sum_nm d_n e_m / (n + m + 1)`` (``d_n``: the
  ``t^n`` coefficient times ``h^n``; remainder below ``4^36 / 36! = 1e-20``, terms up to
  ``e^4``: 1e-14 of rounding);
* every product with a fast exponential: ``int e^((l_j + l_k) t) = (e^(l_j h) e^(l_k h) -
  1) / (l_j + l_k)`` as bilinear forms with the Cauchy matrix ``1 / (l_j + l_k)`` (one
  exponential per rate), ``h expm1(z) / z`` where ``|z| = |l_j + l_k| h < 1`` (a mode
  with itself when lightly damped, two close modes: the difference would cancel), and
  ``int t^q e^(l t)``
  for the polynomial's terms (:func:`power_exp_integrals`).

Cost per run: O(rates x terms) exponentials' powers and O(rates x fast rates) products,
with one exponential per rate: a chattering contact's runs (15 000 of them, 0.3 us to 2
ms, 301 rates up to 2e6 rad/s) have no fast rate but the stiffest few. Exact to rounding
(1e-16 to 1e-12 of the integral against quadratures) at any rate and length: a pole of
3e7 rad/s in a 2 s contact costs what a slow one does.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["product_integrals", "power_exp_integrals", "TAYLOR_TERMS", "TAYLOR_RADIUS",
           "SMALL"]

#: a rate is slow over a run of ``h`` s where ``|l| h <=`` this
TAYLOR_RADIUS = 4.0
#: Taylor terms for the slow rates (remainder ``TAYLOR_RADIUS^36 / 36! = 1e-20``)
TAYLOR_TERMS = 36
#: below this ``|l_j + l_k| h`` a product with a fast rate is integrated by ``expm1`` (a
#: kept entry's rounding is ``eps / (|l_j + l_k| h)``: 1e-3 lost 1e-8 on two close modes)
SMALL = 1.0
_N = np.arange(TAYLOR_TERMS)
_INVERSE_FACTORIAL = 1.0 / np.array([math.factorial(int(i)) for i in _N], float)
_WEIGHTS = 1.0 / (_N[:, None] + _N[None, :] + 1.0)


def product_integrals(rates, k, runs, pairs) -> np.ndarray:
    """``sum over runs of int_0^h a(t) b(t) dt`` for each row pair ``(a, b)`` of ``pairs``.

    Parameters
    ----------
    rates : numpy.ndarray
        The phase's rates ``l_j`` (1/s, complex, conjugate pairs folded), shape (m,).
    k : int
        Terms of the polynomial part.
    runs : list of (numpy.ndarray, numpy.ndarray, float)
        Per run, the rows' polynomial coefficients (rows, k) (of ``t^q``), exponential
        coefficients (rows, m) (row ``= Re sum_j c_j e^(l_j t)`` plus the polynomial) and
        its length ``h`` (s).
    pairs : sequence of (int, int)
        Row pairs.

    Returns
    -------
    numpy.ndarray
        Shape (len(pairs),); NaN where a product of exponentials would overflow (a rate
        growing by ``e^350`` over a run) or a run's length is not finite.
    """
    lam = np.asarray(rates, dtype=complex)
    if k > TAYLOR_TERMS:
        raise ValueError(f"a polynomial part of {k} terms exceeds the Taylor series' "
                         f"{TAYLOR_TERMS}")
    fastest = float(np.max(np.abs(lam))) if lam.size else 0.0
    growth = 2.0 * max(float(np.max(lam.real)) if lam.size else 0.0, 0.0)
    slow_runs, fast_runs = [], []
    for run in runs:
        if not np.isfinite(run[2]) or growth * run[2] > 700.0:
            return np.full(len(pairs), np.nan)       # a product e^(2 Re(l) h) overflows
        (slow_runs if run[2] * fastest <= TAYLOR_RADIUS else fast_runs).append(run)
    total = _all_slow(lam, k, slow_runs, pairs)
    cauchy = _Cauchy(lam)
    for poly, expo, h in fast_runs:
        fast = np.abs(lam) * h > TAYLOR_RADIUS
        slow = ~fast
        # the polynomial and the slow exponentials by their Taylor series
        total += _taylor_integrals(lam[slow], k, np.array([h]), poly[None],
                                   expo[None][:, :, slow], pairs)
        e = np.exp(lam * h)
        powers = power_exp_integrals(lam[fast], h, k) if k else None     # (k, m_f)
        # exponential products with a fast factor: (any, fast) and (fast, slow)
        blocks = [cauchy.block(rows, cols, h) for rows, cols in
                  ((np.arange(lam.size), np.flatnonzero(fast)),
                   (np.flatnonzero(fast), np.flatnonzero(slow)))]
        for i, (a, b) in enumerate(pairs):
            ca, cb = expo[a], expo[b]
            term = sum(_Cauchy.apply(block, ca, cb, e) for block in blocks)
            value = 0.5 * float(term.real)
            if k:
                value += float(np.real(poly[a] @ powers @ cb[fast]
                                       + poly[b] @ powers @ ca[fast]))
            total[i] += value
    return total if np.all(np.isfinite(total)) else np.full(len(pairs), np.nan)


class _Cauchy:
    """``int_0^h e^((l_j + l_k) t) dt = (e^(l_j h) e^(l_k h) - 1) / (l_j + l_k)``, and the
    same with ``conj(l_k)``, as bilinear forms on a block of rate pairs: the Cauchy
    matrices ``1 / (l_j + l_k)`` once per phase, one exponential per rate per run. A kept
    entry's rounding is ``eps / (|l_j + l_k| h)`` of its value; where ``|l_j + l_k| h <``
    :data:`SMALL` (a mode with itself when lightly damped, two close modes) the entry
    leaves the matrix (its ``1 / mu``, up to 1e10, would round the whole sum) and is ``h
    expm1(z) / z`` instead."""

    def __init__(self, lam):
        self.sums = (np.add.outer(lam, lam), np.add.outer(lam, lam.conj()))
        self.sizes = [np.abs(mu) for mu in self.sums]
        self.inverse = [np.divide(1.0, mu, out=np.zeros_like(mu), where=size > 0.0)
                        for mu, size in zip(self.sums, self.sizes)]

    def block(self, rows, cols, h):
        """The block ``rows x cols`` for a run of ``h`` s: per Cauchy matrix, its kept
        entries and the exact integrals of the others, with their indices."""
        if rows.size == 0 or cols.size == 0:
            return None
        sub = np.ix_(rows, cols)
        parts = []
        for mu, size, inverse in zip(self.sums, self.sizes, self.inverse):
            close = size[sub] * h < SMALL
            j, k = np.nonzero(close)
            exact = h * _expm1_ratio(mu[rows[j], cols[k]] * h)
            parts.append((np.where(close, 0.0, inverse[sub]), j, k, exact))
        return rows, cols, parts

    @staticmethod
    def apply(block, ca, cb, e):
        """``sum_(j, k in the block) ca_j cb_k int e^((l_j + l_k) t) + ca_j conj(cb_k)
        int e^((l_j + conj l_k) t)`` over the run; ``e = e^(l h)``."""
        if block is None:
            return 0.0
        rows, cols, parts = block
        cr, er = ca[rows], e[rows]
        value = 0.0 + 0.0j
        for conj, (kept, j, k, exact) in enumerate(parts):
            other, e_other = ((cb[cols], e[cols]) if not conj
                              else (cb[cols].conj(), e[cols].conj()))
            value += (cr * er) @ kept @ (other * e_other) - cr @ kept @ other
            if j.size:
                value += np.sum(cr[j] * other[k] * exact)
        return value


def _all_slow(lam, k, runs, pairs, batch=128):
    """:func:`product_integrals` of runs with no fast rate, by their Taylor series,
    ``batch`` runs at a time."""
    total = np.zeros(len(pairs))
    for first in range(0, len(runs), batch):
        chunk = runs[first:first + batch]
        total += _taylor_integrals(lam, k, np.array([r[2] for r in chunk]),
                                   np.stack([r[0] for r in chunk]),
                                   np.stack([r[1] for r in chunk]), pairs)
    return total


def _taylor_integrals(lam, k, h, poly, expo, pairs):
    """``sum over runs of h sum_nm d_n e_m / (n + m + 1)`` per row pair: the products of the
    rows' Taylor series (``d_n``: the ``t^n`` coefficient times ``h^n``, from the
    polynomial ``poly`` (B, rows, k) and the exponentials ``expo`` (B, rows, m) over
    ``lam`` (m,)) for runs of lengths ``h`` (B,)."""
    z = lam[None, :] * h[:, None]                                        # (B, m)
    powers = z[:, :, None] ** _N * _INVERSE_FACTORIAL                    # (B, m, N)
    d = np.einsum("brm,bmn->brn", expo, powers).real                     # (B, rows, N)
    if k:
        d[:, :, :k] += poly * h[:, None, None] ** np.arange(k)
    return np.array([float(np.einsum("b,bn,nm,bm->", h, d[:, a], _WEIGHTS, d[:, b]))
                     for a, b in pairs])


def _expm1_ratio(z):
    """``(e^z - 1) / z`` elementwise (1 at ``z = 0``), accurate for small ``|z|``; inf or
    NaN where ``e^z`` overflows."""
    z = np.asarray(z, dtype=complex)
    tiny = np.abs(z) < 1e-8
    safe = np.where(tiny, 1.0, z)
    with np.errstate(over="ignore", invalid="ignore"):
        return np.where(tiny, 1.0 + 0.5 * z, np.expm1(safe) / safe)


def power_exp_integrals(lam, h, k):
    """``int_0^h t^q e^(lam_j t) dt`` for ``q < k``, shape (k, len(lam)), complex.

    Where ``|lam h| < 1``, the series ``h^(q+1) sum_n (lam h)^n / (n! (n + q + 1))`` (30
    terms: below rounding); elsewhere the recurrence ``K_q = (h^q e^(lam h) - q K_(q-1)) /
    lam`` from ``K_0 = (e^(lam h) - 1) / lam``, whose rounding grows by up to ``q! /
    |lam h|^q`` (at ``|lam h| = 1``: 2e-14 relative at ``q = 5``, 1e-10 at ``q = 9``; a
    phase's polynomial part has a few terms: the rigid bodies', ``J`` and a load's).
    """
    lam = np.asarray(lam, dtype=complex)
    z = lam * h
    out = np.empty((k, lam.size), complex)
    small = np.abs(z) < 1.0
    n = _N[:30]
    terms = z[small, None] ** n[None, :] * _INVERSE_FACTORIAL[:30]
    big = ~small
    lam_big, e_big = lam[big], np.exp(z[big])
    prev = None
    for q in range(k):
        out[q, small] = h ** (q + 1) * (terms / (n + q + 1)).sum(axis=1)
        cur = ((e_big - 1.0) / lam_big if q == 0
               else (h ** q * e_big - q * prev) / lam_big)
        out[q, big] = cur
        prev = cur
    return out
