"""Saint-Venant's mass-on-fixed-rod problem by the method of characteristics: the
closed-form piecewise solution behind :func:`data_synth.reference_impacts.mass_on_fixed_rod`
(the derivation is in that module's docstring). Every integral of ``exp(-gamma r) r^n`` is
evaluated in closed form, so the solution is exact to rounding."""

from __future__ import annotations

import math

import numpy as np
from numpy.polynomial import polynomial as npoly
from scipy.optimize import brentq, minimize_scalar
from scipy.special import gammainc, gammaln


_MAX_PIECES = 200_000


def _exp_moments(gamma: float, r, nmax: int) -> np.ndarray:
    """``J[..., n] = int_0^r exp(-gamma s) s^n ds`` for ``n = 0..nmax``, ``r >= 0``.

    Exact to rounding: a power series for ``gamma r < 1``, else the regularised lower
    incomplete gamma function ``J_n = n! gamma^-(n+1) P(n+1, gamma r)``.
    """
    r = np.asarray(r, dtype=float)
    n = np.arange(nmax + 1, dtype=float)
    rr = np.maximum(r, 0.0)[..., None]
    x = gamma * rr
    out = np.empty(rr.shape[:-1] + (nmax + 1,))
    small = (x < 1.0)[..., 0]
    if np.any(small):
        rs = rr[small]
        xs = x[small]
        # sum_k (-x)^k / (k! (n + k + 1)); 40 terms: the remainder is < 1/40! for x < 1
        terms = np.zeros(rs.shape[:-1] + (nmax + 1,))
        powk = np.ones_like(xs)
        for kk in range(40):
            terms = terms + powk / (math.factorial(kk) * (n + kk + 1.0))
            powk = powk * (-xs)
        out[small] = rs ** (n + 1.0) * terms
    big = ~small
    if np.any(big):
        xb = x[big]
        logpref = gammaln(n + 1.0) - (n + 1.0) * math.log(gamma)
        out[big] = np.exp(logpref) * gammainc(n + 1.0, xb)
    return out


def _exp_poly_integral(coef, gamma: float, r):
    """``int_0^r exp(-gamma s) q(s) ds`` for polynomial coefficients ``coef`` (ascending)."""
    coef = np.asarray(coef, dtype=float)
    J = _exp_moments(gamma, r, len(coef) - 1)
    return J @ coef


def _shift(coef, d: float, beta: float) -> np.ndarray:
    """Coefficients of ``exp(-beta d) q(d + r)`` in ``r`` (re-centring an exp-polynomial)."""
    coef = np.asarray(coef, dtype=float)
    if d == 0.0:
        return coef.copy()
    deg = len(coef) - 1
    out = np.zeros(deg + 1)
    # Taylor shift: q(d + r) = sum_j r^j q^(j)(d) / j!
    c = coef.copy()
    for j in range(deg + 1):
        out[j] = npoly.polyval(d, c) / math.factorial(j)
        c = npoly.polyder(c) if len(c) > 1 else np.zeros(1)
    return out * math.exp(-beta * d)


def _first_down_crossing(p, r_end: float):
    """First ``r`` in ``(0, r_end)`` where the polynomial ``p`` goes from > 0 to < 0.

    ``p(0) > 0`` is assumed. Between consecutive real critical points the polynomial
    is monotonic, so checking signs at them brackets every crossing.
    """
    p = np.trim_zeros(np.asarray(p, dtype=float), "b")
    if len(p) <= 1:
        return None
    dp = npoly.polyder(p)
    pts = [0.0, r_end]
    if len(np.trim_zeros(dp, "b")) > 1:
        roots = npoly.polyroots(dp)
        real = roots[np.abs(roots.imag) <= 1e-9 * (1.0 + np.abs(roots.real))].real
        pts.extend(float(x) for x in real if 0.0 < x < r_end)
    pts.extend(np.linspace(0.0, r_end, 33)[1:-1])
    pts = np.unique(pts)
    vals = npoly.polyval(pts, p)
    for i in range(len(pts) - 1):
        if vals[i] > 0.0 and vals[i + 1] < 0.0:
            return brentq(lambda r: npoly.polyval(r, p), pts[i], pts[i + 1],
                          xtol=1e-16, rtol=4 * np.finfo(float).eps, maxiter=200)
    return None


# --------------------------------------------------------------------------------------
# mass on a fixed-free rod
# --------------------------------------------------------------------------------------

class _FixedRodSolution:
    """Piecewise exp-polynomial solution of the mass / fixed-rod problem."""

    def __init__(self, M: float, m: float, T: float, v0: float, first_only: bool):
        self.M, self.m, self.T, self.v0 = M, m, T, v0
        self.Z = m / T
        self.beta = m / M
        self.first_only = first_only
        self._build()

    # -- construction ------------------------------------------------------------------
    def _build(self):
        T, v0, beta = self.T, self.v0, self.beta
        starts, ends, contact_flags, Qs, Hs = [], [], [], [], []
        V, X, W, A = [], [], [], []
        t_cur, contact = 0.0, True
        v, x, w, acum = v0, 0.0, 0.0, 0.0
        k_hist = -1
        intervals = []
        contact_start = 0.0
        t_done = None
        first = None
        seps = []
        scale = v0 * T  # displacement scale for the gap tolerance
        n_iter = 0
        while True:
            n_iter += 1
            if n_iter > _MAX_PIECES:
                raise RuntimeError("mass_on_fixed_rod: too many solution pieces; the contact "
                                   "sequence did not terminate")
            if k_hist < 0:
                H = np.zeros(1)
                hist_break = 2.0 * T
            else:
                d = (t_cur - 2.0 * T - starts[k_hist]) / T
                H = _shift(Qs[k_hist], max(d, 0.0), beta)
                hist_break = ends[k_hist] + 2.0 * T
            stop_is_done = t_done is not None and t_done <= hist_break
            t_stop = t_done if stop_is_done else hist_break
            r_end = (t_stop - t_cur) / T

            if contact:
                Q = npoly.polyadd(npoly.polysub(H, 2.0 * beta * npoly.polyint(H)), [v])
                p = npoly.polyadd(Q, H)
                if npoly.polyval(0.0, p) <= 0.0:
                    # the force would jump to a tension: separation right here
                    r1, separated = 0.0, True
                else:
                    r_s = _first_down_crossing(p, r_end)
                    separated = r_s is not None
                    r1 = r_s if separated else r_end
                if r1 > 0.0:
                    starts.append(t_cur)
                    contact_flags.append(True)
                    Qs.append(Q)
                    Hs.append(H)
                    V.append(v)
                    X.append(x)
                    W.append(w)
                    A.append(acum)
                    vq = npoly.polysub(Q, H)
                    x = x + T * _exp_poly_integral(vq, beta, r1)
                    w = x
                    acum = acum + T * _exp_poly_integral(npoly.polymul(Q, Q), 2 * beta, r1)
                    v = math.exp(-beta * r1) * npoly.polyval(r1, vq)
                    t_new = t_cur + r1 * T if separated else t_stop
                    ends.append(t_new)
                    t_cur = t_new
                if separated:
                    contact = False
                    intervals.append((contact_start, t_cur))
                    seps.append((t_cur, v))
                    if first is None:
                        first = (t_cur, v)
                    if self.first_only or v <= 0.0:
                        t_done = t_cur + 4.0 * T
                    else:
                        t_done = None
                    continue
                if not stop_is_done:
                    k_hist += 1
                continue

            # free flight
            Q = -H
            check = not self.first_only
            r_c = None
            if check:
                gap0 = w - x
                vel = v

                def gap(r, H=H, gap0=gap0, vel=vel):
                    return (gap0 - vel * T * np.asarray(r)
                            - 2.0 * T * _exp_poly_integral(H, beta, r))

                r_c = self._first_gap_closure(gap, r_end, scale)
            r1 = r_c if r_c is not None else r_end
            if r1 > 0.0:
                starts.append(t_cur)
                contact_flags.append(False)
                Qs.append(Q)
                Hs.append(H)
                V.append(v)
                X.append(x)
                W.append(w)
                A.append(acum)
                x = x + v * T * r1
                w = w - 2.0 * T * _exp_poly_integral(H, beta, r1)
                acum = acum + T * _exp_poly_integral(npoly.polymul(H, H), 2 * beta, r1)
                t_new = t_cur + r1 * T if r_c is not None else t_stop
                ends.append(t_new)
                t_cur = t_new
            if r_c is not None:
                w = x  # touching again
                contact = True
                contact_start = t_cur
                t_done = None
                continue
            if stop_is_done:
                break
            k_hist += 1

        self.starts = np.array(starts)
        self.ends = np.array(ends)
        self.is_contact = np.array(contact_flags, dtype=bool)
        deg = max(len(q) for q in Qs + Hs)
        self.Qc = np.zeros((len(Qs), deg))
        self.Hc = np.zeros((len(Hs), deg))
        for i, (q, h) in enumerate(zip(Qs, Hs)):
            self.Qc[i, : len(q)] = q
            self.Hc[i, : len(h)] = h
        self.Q2c = np.array([np.convolve(q, q) for q in self.Qc])
        self.V, self.X, self.W, self.A = map(np.array, (V, X, W, A))
        self.t_end = t_cur  # end of the built pieces: last separation + 4T
        self.x_end, self.v_end, self.w_end, self.a_end = x, v, w, acum
        self.intervals = tuple(intervals)
        self.separations = tuple(seps)
        self.first_separation = first
        self.last_separation = seps[-1][0]

    def _first_gap_closure(self, gap, r_end: float, scale: float):
        """First ``r`` in ``(0, r_end]`` where the gap closes (changes sign to < 0)."""
        tol = 1e-13 * scale
        r = np.linspace(0.0, r_end, 257)
        g = gap(r)
        bad = np.nonzero(g[1:] < -tol)[0]
        cand = None
        if bad.size:
            cand = bad[0] + 1
        # hidden dips between samples: refine every sampled local minimum before cand
        last = cand if cand is not None else len(r) - 1
        for j in range(1, last):
            if g[j] <= g[j - 1] and g[j] <= g[j + 1]:
                res = minimize_scalar(lambda s: float(gap(s)), bounds=(r[j - 1], r[j + 1]),
                                      method="bounded", options={"xatol": 1e-14})
                if res.fun < -tol:
                    lo = r[j - 1]
                    return brentq(lambda s: float(gap(s)), lo, res.x, xtol=1e-16,
                                  rtol=4 * np.finfo(float).eps, maxiter=200)
        if cand is None:
            return None
        pos = np.nonzero(g[:cand] > 0.0)[0]
        if pos.size == 0:
            # the gap never opened (grazing within rounding): closed at the piece start
            return r[0]
        lo = r[pos[-1]]
        return brentq(lambda s: float(gap(s)), lo, r[cand], xtol=1e-16,
                      rtol=4 * np.finfo(float).eps, maxiter=200)

    # -- evaluation --------------------------------------------------------------------
    def _locate(self, t):
        j = np.searchsorted(self.starts, t, side="right") - 1
        return np.clip(j, 0, len(self.starts) - 1)

    def _horner(self, C, r):
        out = np.zeros_like(r)
        for k in range(C.shape[1] - 1, -1, -1):
            out = out * r + C[:, k]
        return out

    def _moments_dot(self, C, gamma, r):
        J = _exp_moments(gamma, r, C.shape[1] - 1)
        return np.einsum("ij,ij->i", J, C)

    def cumulative_a2(self, t):
        """``int_0^t a(tau)^2 dtau`` for ``0 <= t < t_end`` (0 for ``t < 0``)."""
        t = np.asarray(t, dtype=float)
        out = np.zeros_like(t)
        inside = (t >= 0.0) & (t < self.t_end)
        if np.any(inside):
            ti = t[inside]
            j = self._locate(ti)
            r = (ti - self.starts[j]) / self.T
            out[inside] = self.A[j] + self.T * self._moments_dot(self.Q2c[j], 2 * self.beta, r)
        out[t >= self.t_end] = self.a_end
        return out

    def evaluate(self, t):
        """Force, mass velocity, mass displacement y1, rod-end displacement y2, rod energy."""
        t = np.asarray(t, dtype=float)
        T, beta, Z = self.T, self.beta, self.Z
        force = np.zeros_like(t)
        vel = np.full_like(t, self.v0)
        y1 = self.v0 * np.minimum(t, 0.0)
        y2 = np.zeros_like(t)
        energy = np.zeros_like(t)

        inside = (t >= 0.0) & (t < self.t_end)
        if np.any(inside):
            ti = t[inside]
            j = self._locate(ti)
            r = (ti - self.starts[j]) / T
            Q = self.Qc[j]
            H = self.Hc[j]
            ex = np.exp(-beta * r)
            a = ex * self._horner(Q, r)
            ah = ex * self._horner(H, r)
            c = self.is_contact[j]
            f_i = np.where(c, Z * (a + ah), 0.0)
            v_i = np.where(c, a - ah, self.V[j])
            x_c = self.X[j] + T * self._moments_dot(Q - H, beta, r)
            x_f = self.X[j] + self.V[j] * T * r
            w_f = self.W[j] - 2.0 * T * self._moments_dot(H, beta, r)
            force[inside] = f_i
            vel[inside] = v_i
            y1[inside] = np.where(c, x_c, x_f)
            y2[inside] = np.where(c, x_c, w_f)
            energy[inside] = Z * (self.cumulative_a2(ti) - self.cumulative_a2(ti - 2.0 * T))

        after = t >= self.t_end
        if np.any(after):
            ta = t[after]
            vel[after] = self.v_end
            y1[after] = self.x_end + self.v_end * (ta - self.t_end)
            # free vibration of the end is 4T-periodic from the last separation
            ts = self.last_separation
            tm = ts + np.mod(ta - ts, 4.0 * T)
            tm = np.minimum(tm, np.nextafter(self.t_end, -np.inf))
            j = self._locate(tm)
            r = (tm - self.starts[j]) / T
            y2[after] = self.W[j] - 2.0 * T * self._moments_dot(self.Hc[j], beta, r)
            energy[after] = Z * (self.a_end
                                 - self.cumulative_a2(np.array([self.t_end - 2 * T]))[0])
        return force, vel, y1, y2, energy

    def impulse(self, t_from: float, t_to: float) -> float:
        """``int f dt`` over contact pieces inside ``[t_from, t_to]`` (closed form)."""
        total = 0.0
        for i in np.nonzero(self.is_contact)[0]:
            a0, a1 = max(self.starts[i], t_from), min(self.ends[i], t_to)
            if a1 <= a0:
                continue
            r0 = (a0 - self.starts[i]) / self.T
            r1 = (a1 - self.starts[i]) / self.T
            pf = self.Qc[i] + self.Hc[i]
            total += self.Z * self.T * (_exp_poly_integral(pf, self.beta, r1)
                                        - _exp_poly_integral(pf, self.beta, r0))
        return float(total)

    def rod_energy_at(self, t: float) -> float:
        return float(self.evaluate(np.array([t]))[4][0])



def _energy_after(sol: _FixedRodSolution) -> float:
    """Energy (J) left in the rod after the last contact."""
    return sol.Z * (sol.a_end - float(sol.cumulative_a2(np.array([sol.t_end - 2 * sol.T]))[0]))


# --------------------------------------------------------------------------------------
# two free-free rods with equal transit times
# --------------------------------------------------------------------------------------

