"""Closed-form phases of the exact engine with a harmonic load, and their event search.

A phase is linear and autonomous up to the harmonic excitation::

    x' = M x + Bh xh(t),      xh(t) = Re(h e^{i Omega t})      (x real, shape (n,))

``M`` is decomposed once per kind of phase (free flight, stuck contact, spring contact)
by :class:`impactpred.engine.spectral.SpectralPhase`: a nilpotent block (the damper
mass's free flight, constants, a rigid constraint) and a diagonalised rest. With the
particular solution ``xp(t) = Re(X e^{i Omega t})``, ``X = (i Omega - M)^-1 Bh h``, any
output row ``r`` of the state is, on a phase starting at ``t0``,

    r x(t0 + tau) = Re(sum_j b_j e^{lambda_j tau}) + poly(tau)

(one term per eigenvalue with ``Im >= 0``, conjugates folded in, the excitation as the
term ``lambda = i Omega``): coefficient arithmetic, exact to rounding, evaluated for a
whole vector of times in one call.

Event search: :func:`search_event`, the certified multilevel search of
:func:`impactpred.engine.search.first_event` (compiled) on a phase's rows.
"""

from __future__ import annotations

import math

import numpy as np

from .search import first_event
from .spectral import DefectiveSpectrum, SpectralPhase

__all__ = ["PhaseKind", "search_event", "evaluate"]

#: a forcing frequency is resonant where the shift ``i omega - lambda`` on the phase's
#: non-zero eigenvalues has a condition number above this (relative distance to the mode
#: below about 1e-13 for a lone mode)
_RESONANT_COND = 1e13


class PhaseKind:
    """The exact solution of one kind of phase, decomposed once.

    Parameters
    ----------
    M_aug : ndarray, shape (n + 2, n + 2)
        Phase matrix on ``[x, xh]`` (``xh``: the two harmonic states, last).
    h : ndarray of complex, shape (2,)
        ``xh(t) = Re(h e^{i omega t})``.
    omega : float
        Excitation frequency (rad/s, or per unit of time ``time_unit``).
    event_rows, output_rows : ndarray, shape (k, n + 2)
        Rows on ``[x, xh]``: the event functions (the phase ends when one turns negative)
        and the outputs sampled.
    update_of : (PhaseKind, ndarray, ndarray) or None, keyword-only
        ``(free, b, r)``: ``M_aug`` is ``free``'s plus ``outer(b, r)`` (shape (n + 2,)
        each; a contact force fed back). The state part is then split through ``free``'s
        form by the rank-one route (:mod:`.rank_one`, checked, with the general route as
        its fallback), as the exact solver's contact phase.
    time_unit : float, keyword-only
        The unit of time (s) of ``M_aug`` and ``omega`` (a dimensionless form's), for the
        frequency an error names (Hz).
    """

    def __init__(self, M_aug, h, omega, event_rows, output_rows, *, name, update_of=None,
                 time_unit=1.0):
        n = M_aug.shape[0] - 2
        M, Bh = M_aug[:n, :n], M_aug[:n, n:]
        self.name, self.n, self.omega, self.M_aug = name, n, omega, M_aug
        if update_of is not None:
            free, b, r = update_of
            update_of = (free.spectral, np.asarray(b, float)[:n], np.asarray(r, float)[:n])
        try:
            sp = SpectralPhase(M, update_of=update_of)
        except DefectiveSpectrum as exc:
            raise ValueError(f"the {name} phase's matrix is defective ({exc}): two modes of "
                             "the coupled system coincide; perturb a parameter") from exc
        lam = sp.lam.copy()
        # rounding of undamped poles: no growth
        lam.real = np.minimum(lam.real, 0.0)
        keep = lam.imag >= 0.0
        weight = np.where(lam.imag > 0.0, 2.0, 1.0)[keep]
        shift = 1j * omega * np.eye(n) - M
        # Resonance: the condition number of the shift on the diagonalised part, in its
        # eigenbasis (max over min of |i omega - lambda|; the eigenvectors' own conditioning
        # is SpectralPhase's check). Scale-free: a change of the unit of time scales omega
        # and every lambda alike. The nilpotent block (zero eigenvalues: the free mass's
        # double integrator, constants) is no resonance for omega > 0, its inverse a finite
        # series in 1 / (i omega); cond(i omega - M) counted it, ~ (|M| / omega)^2 on a
        # dimensionless form, and refused slow forcing (1e-6 Hz of a 10 Hz primary).
        gaps = np.abs(1j * omega - sp.lam)
        if gaps.size and max(omega, float(np.max(gaps))) > _RESONANT_COND * np.min(gaps):
            hz = omega / (2 * np.pi * time_unit)
            raise ValueError(f"the excitation frequency {hz!r} Hz coincides "
                             f"with an undamped mode of the {name} phase: the closed form has "
                             "no term for the resonant growth (t e^(i Omega t)); move the "
                             "frequency off the mode by a relative 1e-9 or more (a rounding "
                             "error of about 2e-7 of the response, said in the result's "
                             "notes) or give the mode some damping")
        #: the relative rounding error of the phase's response near a resonance: the free
        #: and forced parts, each ``omega / |i omega - lambda|`` times the response, cancel
        #: (an undamped primary forced 1e-10 off its mode: 2e-6, measured 3e-6)
        self.resonance_error = float(np.finfo(float).eps * omega / max(np.min(gaps), 1e-300)
                                     if omega > 0 and gaps.size else 0.0)
        self.X = np.linalg.solve(shift, Bh @ h)          # particular solution amplitude
        self.spectral = sp
        self.h = np.asarray(h, complex)
        self.lam = np.concatenate([lam[keep], [1j * omega]])
        self.V = sp.s1v[:, keep] * weight
        self.Vinv = sp.in1[keep]
        self.k = sp.k
        self.in0 = sp.in0
        self.S0P = [sp.s0 @ p for p in sp.powers]       # x_poly(tau) = sum_j tau^j S0P_j c0
        self.max_rate = float(np.max(np.abs(self.lam)))
        self.order_desc = np.argsort(-np.abs(self.lam), kind="stable")
        self.abs_lam = np.abs(self.lam)
        self.abs_lam4 = self.abs_lam ** 4
        self.cuts = {}            # level cuts of the event search, by first cut
        self.powers_k = np.arange(self.k)
        self.event = self._rows(np.atleast_2d(event_rows))
        self.output = self._rows(np.atleast_2d(output_rows))

    def _rows(self, rows):
        n = self.n
        rx, rh = rows[:, :n], rows[:, n:]
        rp = (np.stack([rx @ p for p in self.S0P], axis=1) if self.k
              else np.zeros((rows.shape[0], 0, 0)))      # (rows, degree, k)
        return (rx @ self.V, rp, rx @ self.X + rh @ self.h)

    # ---------------------------------------------------------------- per phase
    def start(self, x, t0):
        """Coordinates ``(c1, c0, e^{i omega t0})`` of the state ``x`` at time ``t0``."""
        rot = complex(math.cos(self.omega * t0), math.sin(self.omega * t0))
        dev = x - (self.X * rot).real
        return self.Vinv @ dev, self.in0 @ dev, rot

    def coefficients(self, rows, coords):
        """``(b, poly)`` of ``rows`` (``self.event`` or ``self.output``) for ``coords``."""
        rv, rp, rx = rows
        c1, c0, rot = coords
        b = np.empty((rv.shape[0], self.lam.size), complex)
        b[:, :-1] = rv * c1
        b[:, -1] = rx * rot
        poly = rp @ c0 if self.k else np.zeros((rv.shape[0], 0))
        return b, poly

    def state(self, coords, tau):
        """The state ``x`` (shape (n,)) at ``tau`` after the phase's start."""
        c1, c0, rot = coords
        e = np.exp(self.lam[:-1] * tau)
        x = (self.V @ (e * c1)).real
        if self.k:
            x = x + sum((tau ** j) * (p @ c0) for j, p in enumerate(self.S0P))
        return x + (self.X * (rot * e_i(self.omega * tau))).real


def e_i(phi):
    return complex(math.cos(phi), math.sin(phi))


def _poly_derivative(poly):
    """Coefficients of the derivative of the rows ``poly`` (same shape)."""
    out = np.zeros_like(poly)
    k = poly.shape[1]
    if k > 1:
        out[:, :-1] = poly[:, 1:] * np.arange(1, k)
    return out


def evaluate(lam, b, poly, taus, derivatives=(0,)):
    """Rows (k x len(taus)) and time derivatives of ``Re(b e^{lam tau}) + poly(tau)``."""
    taus = np.asarray(taus, dtype=float)
    e = np.exp(np.outer(lam, taus))
    k = poly.shape[1]
    tpow = taus[None, :] ** np.arange(k)[:, None] if k else None
    out = []
    for d in derivatives:
        value = ((b * lam ** d) @ e).real if d else (b @ e).real
        if k > d:
            p = poly
            for _ in range(d):
                p = _poly_derivative(p)
            value += p @ tpow
        out.append(value)
    return out


def _cubic_min(fa, fb, da, db, h):
    """Minimum over the step of the cubic Hermite interpolant (arrays of any shape)."""
    delta = fb - fa
    dah = da * h
    c2 = 3.0 * delta - (2.0 * dah + db * h)
    c3 = (dah + db * h) - 2.0 * delta
    # p'(u) = da h + 2 c2 u + 3 c3 u^2 on u in [0, 1]; candidates: its roots (c3 != 0)
    # and the root of the linear case (c3 == 0); denominators guarded, no warnings
    out = np.minimum(fa, fb)
    sq = np.sqrt(np.maximum(c2 * c2 - 3.0 * c3 * dah, 0.0))
    z3, z2 = c3 == 0.0, c2 == 0.0
    d3 = np.where(z3, 1.0, 3.0 * c3)
    d2 = np.where(z2, 1.0, 2.0 * c2)
    for u, bad in (((-c2 + sq) / d3, z3), ((-c2 - sq) / d3, z3), (-dah / d2, z2)):
        u = np.where(bad, 0.0, np.clip(u, 0.0, 1.0))
        out = np.minimum(out, fa + u * (dah + u * (c2 + u * c3)))
    return out


def search_event(kind, b, poly, tau_max, *, scale, zero_tol, on_boundary, open_rows=()):
    """First ``tau`` in ``(0, tau_max]`` (s) where a row of ``kind`` falls below ``-zero_tol``.

    The certified multilevel search (:func:`impactpred.engine.search.first_event`, see
    there) on the rows ``Re(b e^{lam tau}) + poly(tau)`` of ``kind`` (``b`` (K, m) complex,
    ``poly`` (K, k)); ``scale``, ``zero_tol`` (K,) in the rows' units; ``on_boundary``: the
    phase starts at an event; ``open_rows``: at most one row decided to open there.

    Returns ``(tau, row)``, or ``(None, -1)`` when no row crosses before ``tau_max``.
    """
    if len(open_rows) > 1:
        raise ValueError(f"at most one open row, got {open_rows!r}")
    c = np.ascontiguousarray
    tau, row = first_event(kind.lam, kind.abs_lam, kind.abs_lam4, kind.order_desc,
                           c(b, dtype=complex), c(poly, dtype=float), float(tau_max),
                           c(scale, dtype=float), c(zero_tol, dtype=float), bool(on_boundary),
                           int(open_rows[0]) if len(open_rows) else -1)
    return (None, -1) if row < 0 else (float(tau), int(row))
