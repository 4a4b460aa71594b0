"""Closed-form propagation of a linear autonomous phase ``x' = M x``.

``M`` is split once by an ordered real Schur form and a Sylvester solve into a block
with eigenvalues at 0 (nilpotent: rigid-body motion, constants, integrators) and the
rest, which is diagonalised:

    x(t) = S0 exp(N t) c0 + S1 V exp(Lambda t) c1,     exp(N t) = sum_{j<k} N^j t^j / j!

so any output ``r x(t)`` is a polynomial plus a sum of exponentials ``sum b_j e^{l_j t}``:
coefficient arithmetic, exact to rounding, and evaluated at a whole vector of times in
one numpy call. This is the paper's pole-residue form of the phase's response.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg

__all__ = ["SpectralPhase", "DefectiveSpectrum"]


class DefectiveSpectrum(ValueError):
    """The non-zero part of ``M`` is not safely diagonalisable."""


class SpectralPhase:
    """Spectral form of ``x' = M x`` with fast evaluation of outputs over many times."""

    def __init__(self, M, *, zero_tol=1e-9, max_cond=1e8):
        M = np.asarray(M, dtype=float)
        n = M.shape[0]
        norm = np.linalg.norm(M, 1) or 1.0
        tol = zero_tol * norm
        t, z, k = scipy.linalg.schur(M, output="real",
                                     sort=lambda re, im: np.hypot(re, im) <= tol)
        t11, t12, t22 = t[:k, :k], t[:k, k:], t[k:, k:]
        x = (scipy.linalg.solve_sylvester(t11, -t22, -t12) if 0 < k < n
             else np.zeros((k, n - k)))
        # x_orig = Z [[I, X], [0, I]] [xi0; xi1]
        upper = np.eye(n)
        upper[:k, k:] = x
        s = z @ upper
        s_inv = np.linalg.solve(upper, z.T) if k else z.T
        lam, v = (np.linalg.eig(t22) if k < n else (np.zeros(0, complex), np.zeros((0, 0))))
        if lam.size and np.linalg.cond(v) > max_cond:
            raise DefectiveSpectrum(f"eigenvector condition number {np.linalg.cond(v):.3g}")
        self.n, self.k = n, k
        self.nil = t11
        self.lam = lam
        self.s0 = s[:, :k]
        self.s1v = s[:, k:] @ v if lam.size else np.zeros((n, 0), complex)
        self.in0 = s_inv[:k]
        self.in1 = np.linalg.solve(v, s_inv[k:]) if lam.size else np.zeros((0, n), complex)
        # powers N^j / j! for the polynomial part (N nilpotent: N^k = 0)
        powers = [np.eye(k)]
        for j in range(1, k + 1):
            powers.append(powers[-1] @ t11 / j)
        self.powers = powers[:k] if k else []
        self.max_rate = float(np.max(np.abs(lam))) if lam.size else 0.0

    def coordinates(self, x):
        """``(c0, c1)``: the state in the split coordinates."""
        return self.in0 @ x, self.in1 @ x

    def output_coefficients(self, rows, coords):
        """Polynomial (rows x k) and exponential (rows x m) coefficients of ``rows @ x(t)``."""
        c0, c1 = coords
        rows = np.atleast_2d(rows)
        poly = np.stack([rows @ (self.s0 @ (p @ c0)) for p in self.powers], axis=1) \
            if self.k else np.zeros((rows.shape[0], 0))
        expo = (rows @ self.s1v) * c1[None, :]
        return poly, expo

    def evaluate(self, coefficients, taus, derivative=0):
        """Outputs (rows x len(taus)) at times ``taus`` from ``output_coefficients``."""
        return self.evaluate_orders(coefficients, taus, (derivative,))[0]

    def evaluate_orders(self, coefficients, taus, derivatives=(0, 1)):
        """Outputs and their time derivatives at ``taus``, sharing the exponentials.

        Returns one (rows x len(taus)) array per entry of ``derivatives``.
        """
        poly, expo = coefficients
        taus = np.asarray(taus, dtype=float)
        k = poly.shape[1]
        e = np.exp(np.outer(self.lam, taus)) if expo.shape[1] else None
        powers = taus[None, :] ** np.arange(k)[:, None] if k else None
        out = []
        for d in derivatives:
            value = np.zeros((poly.shape[0], taus.size))
            if k > d:
                factors = np.array([math.perm(j, d) for j in range(d, k)], dtype=float)
                value += (poly[:, d:] * factors) @ powers[:k - d]
            if e is not None:
                value += ((expo * self.lam[None, :] ** d) @ e).real
            out.append(value)
        return out

    def scalar(self, coefficients, tau, derivative=0):
        """One output row's value (or derivative) at one time: the root finders' kernel."""
        poly, expo = coefficients
        value = 0.0
        for j in range(derivative, poly.shape[1]):
            value += poly[0, j] * math.perm(j, derivative) * tau ** (j - derivative)
        if expo.shape[1]:
            value += float(np.dot(expo[0] * self.lam ** derivative,
                                  np.exp(self.lam * tau)).real)
        return value

    def state(self, coords, tau):
        """The full state at one time ``tau``."""
        c0, c1 = coords
        x = np.zeros(self.n)
        if self.k:
            x += self.s0 @ (sum(p * tau**j for j, p in enumerate(self.powers)) @ c0)
        if self.lam.size:
            x += (self.s1v @ (np.exp(self.lam * tau) * c1)).real
        return x
