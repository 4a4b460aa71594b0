r"""Closed-form periodic solution of the impact damper (Masri & Caughey, 1966).

The classical baseline of the impact damper: an undamped primary mass ``M`` on a spring
``K``, forced by ``F0 cos(Omega t)``, carries a container in which a free mass ``m`` moves
with a clearance; impacts are instantaneous with a coefficient of restitution ``e``.
This module gives the symmetric steady state with two impacts per forcing cycle, equally
spaced in time (one on each stop), in closed form, its existence conditions and its
stability (Floquet multipliers of the impact map).

Clearance convention
--------------------
This library's ``clearance`` ``c`` is the free travel on EACH side: the damper mass is
free while ``-c < y - x < c`` (``x`` primary, ``y`` damper mass). Masri & Caughey's ``d``
is the total free travel: ``d = 2 c``.

Nondimensional groups
---------------------
``omega_n = sqrt(K/M)``, ``r = Omega/omega_n``, ``mu = m/M``, lengths in units of the
static deflection ``F0/K`` (``c* = c K/F0``; Masri & Caughey's ``d* = d K/F0 = 2 c*``),
time ``tau = omega_n t``, ``D = 1/(1 - r**2)`` (the linear amplitude, signed), and

    P = (1 - e)(1 + mu)/(1 + e),      Gamma = pi/2 + mu r tan(pi/(2 r)).

Derivation (first principles)
-----------------------------
Put an impact on the upper stop (``y - x = +c``) at ``tau = 0`` and let the forcing be
``cos(r tau + phi)`` there; ``phi`` is the impact phase. After the impact the primary
starts from ``x0`` with velocity ``u``, the damper mass with velocity ``w``; before it
they had ``u-`` and ``w-``. The symmetric solution requires the state half a period
later (``tau = pi/r``, impact on the lower stop) to be minus the state at ``tau = 0``.

1. Damper mass: constant velocity; by symmetry ``w- = -w``, and reaching the lower stop
   at ``tau = pi/r`` gives ``w = -(2 r/pi)(x0 + c)``.
2. Primary: ``x = D cos(r tau + phi) + h(tau)`` with ``h`` a free oscillation at
   ``omega_n``. The particular part is anti-periodic over half a period, so ``h`` must be
   too: ``h(pi/r) = -h(0)``, ``h'(pi/r) = -h'(0-)``. The first gives
   ``h(0) = -h'(0+) tan(pi/(2r))``, the second then gives ``h'(0-) = -h'(0+)``: the free
   part's velocity simply reverses at each impact.
3. Momentum ``u - u- = -2 mu w`` (from ``M u + m w = M u- + m w-`` and ``w- = -w``) with
   step 2 (``u + u- = -2 r D sin(phi)``) gives ``h'(0+) = -mu w``,
   ``h(0) = mu w tan(pi/(2 r))`` (``omega_n = 1``) and ``u = -r D sin(phi) - mu w``.
4. Restitution ``w - u = -e (w- - u-)`` gives ``w = -(1 + e) r D sin(phi)/((1 - e)(1 + mu))``.
5. Writing ``W = w/r`` (a length), steps 1-4 reduce to two linear equations in
   ``(D cos(phi), D sin(phi))``:

       D sin(phi) = -P W,          D cos(phi) = -c - Gamma W,

   so that ``W`` solves the quadratic ``(P**2 + Gamma**2) W**2 + 2 c Gamma W + c**2 - D**2 = 0``:

       W = (-c Gamma +- sqrt((P**2 + Gamma**2) D**2 - P**2 c**2)) / (P**2 + Gamma**2).

   (For ``0 <= e < 1`` this is Masri & Caughey's ``cos(phi) - (Gamma/P) sin(phi) = -c/D``.)
   Then ``x0 = -c - pi W/2``, ``u = r W (P - mu)``, ``u- = r W (P + mu)``,
   damper velocity before the impact ``w- = -r W``, relative approach velocity
   ``w- - u- = -r W (1 + mu + P)``.

Existence: real roots, ``(P**2 + Gamma**2) D**2 >= P**2 c**2`` (at most two solutions);
a positive approach velocity, ``W < 0`` (equivalently ``D sin(phi) > 0``: the impact on
the upper stop happens while the force is decreasing below resonance and increasing above
it); and no intermediate contact: ``|y - x| <= c`` during the flight (checked on a grid
of at least 64 points per half period plus one per 1/64 of a natural period, a grazing
excursion shorter than that may pass unnoticed). A forcing below
``MIN_FREQUENCY_RATIO`` (1e-3) of the natural frequency is refused (``ValueError``): the
grid would take over 64 000 points per half period.

The singular points of the formulas (``r = 1``, where ``D`` and ``Gamma`` are infinite, and
``r = 1/3, 1/5, ...`` where ``tan`` is) are removable: the code multiplies the quadratic by
``cos(pi/(2r))**2``, with ``D cos(pi/(2r)) = cos(pi/(2r))/(1 - r**2)`` written as a ``sinc``,
and integrates the forcing from the impact state in a form that stays finite at ``r = 1``
(``sinc`` again; the primary's motion is never split into two infinite parts). So the
solution is regular at resonance: there ``phi = pi`` and ``w- = pi F0/(4 m omega_n)``.

Amplitude: ``amplitude`` is the primary's maximum displacement ``max |x(t)|`` over the
cycle (equal to half the peak-to-peak value, the solution being symmetric), from the
stationary points of ``x`` found exactly (``brentq`` on ``x'``), not the amplitude of
the first harmonic.

Stability: the half-period map ``G`` = (flight to the next impact, impact, mirror
``state -> -state``, phase ``-pi``) on the post-impact state (forcing phase, ``x``,
``x'``, ``y'``) has the periodic solution as a fixed point; the system being symmetric,
the one-period Poincare map is ``G o G``. Its Jacobian is taken by central finite
differences of this module's own exact flight map (next impact time by Newton), and the
solution is ``stable`` when all Floquet multipliers (eigenvalues of ``J**2``) lie inside
the unit circle (Masri & Caughey derived this condition analytically). The primary being
undamped, two multipliers are close to the unit circle for small ``mu``; within 1e-4 of
it the flag is reported as unreliable in ``notes``. Typically one root of the quadratic
is unstable, and the stable solutions lie in a narrow band of the (``r``, ``c*``) plane,
e.g. for ``mu = 0.1``, ``e = 0.6``: ``c*`` about 4-6 at ``r = 1.1``, 2-3 at ``r = 1.3``,
0.7-1 at ``r = 1.6``, 0.5 at ``r = 2``; and ``c*`` 6-12 below resonance (``r`` 0.6-0.8).

References
----------
S. F. Masri and T. K. Caughey, "On the stability of the impact damper", J. Appl. Mech.
33(3), 586-592 (1966). S. F. Masri, "General motion of impact dampers", J. Acoust. Soc.
Am. 47, 245-248 (1970).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from scipy.optimize import brentq

from modalid.validation import as_nonnegative_scalar, as_positive_scalar

__all__ = ["MasriCaugheySolution", "masri_caughey", "masri_caughey_curve"]

#: the lowest forcing frequency, as a share of the natural one, solved: below it the
#: primary makes over 1000 free oscillations between impacts, each sampled by the check
#: for an intermediate contact (1e-5: 6.4e6 points, 90 s and 4.6 GB; 1e-9: a MemoryError)
MIN_FREQUENCY_RATIO = 1e-3


# --------------------------------------------------------------------------- kernels
# Everything below works in nondimensional units: lengths in F0/K, time omega_n t,
# primary mass 1, damper mass mu, forcing cos(r tau + phi).

def _forced(tau, phi, r):
    """Response to ``cos(r s + phi)`` from rest at ``s = 0``: ``I(tau)`` and ``I'(tau)``.

    ``I(tau) = int_0^tau sin(tau - s) cos(r s + phi) ds``, written with ``sinc`` so that it
    stays exact at and near ``r = 1``.
    """
    tau = np.asarray(tau, dtype=float)
    s1 = np.sinc((1.0 - r) * tau / (2 * np.pi))
    s2 = np.sinc((1.0 + r) * tau / (2 * np.pi))
    a1 = 0.5 * (1.0 + r) * tau + phi
    a2 = 0.5 * (1.0 - r) * tau - phi
    i0 = 0.5 * tau * (np.sin(a1) * s1 + np.sin(a2) * s2)
    i1 = 0.5 * tau * (np.cos(a1) * s1 + np.cos(a2) * s2)
    return i0, i1


def _flight(tau, x0, v0, phi, r):
    """Primary displacement and velocity ``tau`` after the state ``(x0, v0)`` at phase ``phi``."""
    i0, i1 = _forced(tau, phi, r)
    c, s = np.cos(tau), np.sin(tau)
    return x0 * c + v0 * s + i0, -x0 * s + v0 * c + i1


def _roots(mu, r, c, e):
    """Both roots ``(W, phi)`` of the periodicity conditions, or ``[]`` when not real."""
    P = (1.0 - e) * (1.0 + mu) / (1.0 + e)
    # lam = cos(pi/(2r)) / (1 - r**2), regular at r = 1 (-> -pi/4)
    lam = -np.pi * np.sinc((1.0 - r) / (2.0 * r)) / (2.0 * r * (1.0 + r))
    den = (1.0 - r) * (1.0 + r) * lam           # = cos(pi/(2r)); D = Dn/den, Gamma = Gn/den
    Dn = lam
    Gn = 0.5 * np.pi * den + mu * r * math.sin(np.pi / (2.0 * r))
    a2 = P**2 * den**2 + Gn**2
    b = c * Gn * den
    disc = Dn**2 * (P**2 * den**2 + Gn**2) - P**2 * c**2 * den**4
    if a2 == 0.0 or Dn == 0.0 or disc < 0.0:
        return []
    sq = math.sqrt(disc)
    q = -(b + math.copysign(sq, b)) if b != 0.0 else sq
    a0 = c**2 * den**2 - Dn**2
    cands = {q / a2, a0 / q if q != 0.0 else -q / a2}
    sgn = math.copysign(1.0, Dn)
    out = []
    for W in sorted(cands):
        phi = math.atan2(sgn * (-P * W * den), sgn * (-c * den - Gn * W)) % (2 * np.pi)
        out.append((W, phi))
    return out


def _grid(r):
    T = np.pi / r
    n = int(64 * math.ceil(1.0 + 1.0 / r)) + 1
    return np.linspace(0.0, T, n)


def _amplitude(x0, u, phi, r):
    """Exact ``max |x|`` over the half period (stationary points by brentq on ``x'``)."""
    tau = _grid(r)
    x, v = _flight(tau, x0, u, phi, r)
    best = float(np.max(np.abs(x)))
    idx = np.nonzero(np.sign(v[:-1]) * np.sign(v[1:]) < 0)[0]
    for i in idx:
        ts = brentq(lambda t: float(_flight(t, x0, u, phi, r)[1]), tau[i], tau[i + 1],
                    xtol=1e-15, rtol=4 * np.finfo(float).eps)
        best = max(best, abs(float(_flight(ts, x0, u, phi, r)[0])))
    return best


def _no_intermediate_contact(x0, u, w, phi, r, c):
    tau = _grid(r)[1:-1]
    x, _ = _flight(tau, x0, u, phi, r)
    z = x0 + c + w * tau - x
    tol = 1e-9 * (c + abs(x0) + abs(w) * np.pi / r)
    return bool(np.all(z <= c + tol) and np.all(z >= -c - tol))


def _half_map(s, mu, r, c, e, T):
    """Post-impact state on the upper stop -> next impact (lower stop) -> mirrored."""
    psi, x, v, yd = s
    tau = T
    for _ in range(60):
        xt, vt = _flight(tau, x, v, psi, r)
        g = x + 2 * c + yd * tau - xt
        step = g / (yd - vt)
        tau -= step
        if abs(step) <= 1e-15 * T:
            break
    xt, vt = _flight(tau, x, v, psi, r)
    vrel = yd - vt
    vp = vt + mu * (1 + e) * vrel / (1 + mu)
    ydp = yd - (1 + e) * vrel / (1 + mu)
    return np.array([psi + r * tau - np.pi, -xt, -vp, -ydp])


def _multipliers(mu, r, c, e, phi, x0, u, w, scale):
    T = np.pi / r
    s0 = np.array([phi, x0, u, w])
    h = 1e-6 * np.array([1.0, scale, scale * max(r, 1.0), scale * max(r, 1.0)])
    J = np.empty((4, 4))
    for k in range(4):
        dp = s0.copy()
        dm = s0.copy()
        dp[k] += h[k]
        dm[k] -= h[k]
        J[:, k] = (_half_map(dp, mu, r, c, e, T) - _half_map(dm, mu, r, c, e, T)) / (2 * h[k])
    lam = np.linalg.eigvals(J) ** 2
    return tuple(lam[np.argsort(-np.abs(lam))])


# --------------------------------------------------------------------------- public API

@dataclass(frozen=True)
class MasriCaugheySolution:
    """Symmetric two-impacts-per-cycle steady state of the classical impact damper.

    Attributes
    ----------
    primary_mass, damper_mass, stiffness, force_amplitude, freq_hz, clearance, restitution :
        The inputs (SI; ``clearance`` is the free travel on EACH side, ``d = 2 clearance``).
    exists : bool
        The periodic solution exists (real root, positive approach velocity, no
        intermediate contact). When False the numbers below are NaN.
    stable : bool
        All Floquet multipliers inside the unit circle (False when not ``exists``).
    amplitude : float
        Primary steady amplitude ``max |x(t)|`` over the cycle (m) = half peak-to-peak.
    impact_phase : float
        Forcing phase ``2 pi f t + phase`` (rad, in [0, 2 pi)) at the impact of the damper
        mass on the upper stop, for the force ``F0 cos(2 pi f t + phase)``; the impact on
        the lower stop is half a period later (``impact_phase + pi``).
    damper_velocity : float
        Damper-mass velocity just before the upper-stop impact (m/s, > 0).
    primary_velocity : float
        Primary velocity just before that impact (m/s).
    impact_displacement : float
        Primary displacement at that impact (m); the damper mass is at ``+ clearance``.
    multipliers : tuple of complex
        Floquet multipliers of the one-period map, largest modulus first.
    other : MasriCaugheySolution or None
        The second root of the closed form when it also satisfies the existence conditions.
    notes : tuple of str
    """

    primary_mass: float
    damper_mass: float
    stiffness: float
    force_amplitude: float
    freq_hz: float
    clearance: float
    restitution: float
    exists: bool
    stable: bool
    amplitude: float
    impact_phase: float
    damper_velocity: float
    primary_velocity: float
    impact_displacement: float
    multipliers: tuple = ()
    other: MasriCaugheySolution | None = field(default=None, repr=False)
    notes: tuple = ()

    # nondimensional internals (W, phi, x0, u in units of F0/K, omega_n)
    _W: float = field(default=math.nan, repr=False)

    @property
    def mass_ratio(self) -> float:
        """``mu = damper_mass / primary_mass``."""
        return self.damper_mass / self.primary_mass

    @property
    def frequency_ratio(self) -> float:
        """``r = Omega / omega_n``."""
        return 2 * np.pi * self.freq_hz / math.sqrt(self.stiffness / self.primary_mass)

    @property
    def amplitude_without_damper(self) -> float:
        """``|F0 / (K - M Omega**2)|`` (m; ``inf`` at resonance)."""
        den = abs(self.stiffness - self.primary_mass * (2 * np.pi * self.freq_hz) ** 2)
        return self.force_amplitude / den if den > 0 else math.inf

    @property
    def reduction(self) -> float:
        """``amplitude / amplitude_without_damper``."""
        return self.amplitude / self.amplitude_without_damper

    def trajectory(self, t, *, phase=0.0):
        """Primary and damper-mass displacements (m) of the periodic solution at times ``t``.

        Parameters
        ----------
        t : array_like
            Times (s) for the force ``F0 cos(2 pi f t + phase)``.
        phase : float
            Forcing phase (rad), as in ``HarmonicForce(..., phase=)``.

        Returns
        -------
        primary, damper : ndarray
            Absolute displacements, same shape as ``t``; ``damper - primary`` stays within
            ``[-clearance, clearance]``.
        """
        if not self.exists:
            raise ValueError("the Masri-Caughey solution does not exist for these parameters "
                             f"({'; '.join(self.notes)})")
        t = np.asarray(t, dtype=float)
        xs = self.force_amplitude / self.stiffness
        wn = math.sqrt(self.stiffness / self.primary_mass)
        r = self.frequency_ratio
        mu = self.mass_ratio
        c = self.clearance / xs
        P = (1 - self.restitution) * (1 + mu) / (1 + self.restitution)
        W = self._W
        x0, u, w = -c - 0.5 * np.pi * W, r * W * (P - mu), r * W
        Omega = r * wn
        t_imp = (self.impact_phase - phase) / Omega
        Th = np.pi / Omega
        s = np.mod(t - t_imp, 2 * Th)
        second = s >= Th
        s = np.where(second, s - Th, s)
        tau = wn * s
        x, _ = _flight(tau, x0, u, self.impact_phase, r)
        y = x0 + c + w * tau
        sign = np.where(second, -1.0, 1.0)
        return sign * x * xs, sign * y * xs


def _check(name, value, *, strict=True, upper=None):
    """``value`` as a finite float, > 0 (``strict``) or >= 0, at most ``upper``; a bool or a
    non-number is refused (``TypeError``), a value out of range too (``ValueError``)."""
    v = as_positive_scalar(name, value) if strict else as_nonnegative_scalar(name, value)
    if upper is not None and v > upper:
        raise ValueError(f"{name} must be <= {upper:g}, got {value!r}")
    return v


def masri_caughey(*, primary_mass, damper_mass, stiffness, force_amplitude, freq_hz, clearance,
                  restitution) -> MasriCaugheySolution:
    """Closed-form symmetric two-impacts-per-cycle solution of the impact damper.

    Undamped primary ``M x'' + K x = F0 cos(2 pi f t) + impulses``, free damper mass ``m``,
    instantaneous impacts with restitution ``e``; see the module docstring for the
    derivation and the formulas.

    Parameters
    ----------
    primary_mass, damper_mass : float
        ``M`` and ``m`` (kg, > 0).
    stiffness : float
        ``K`` (N/m, > 0).
    force_amplitude : float
        ``F0`` (N, > 0).
    freq_hz : float
        Forcing frequency (Hz, > 0).
    clearance : float
        Free travel on EACH side (m, >= 0); Masri & Caughey's ``d`` is ``2 * clearance``.
    restitution : float
        Coefficient of restitution ``e``, 0 <= e <= 1.

    Returns
    -------
    MasriCaugheySolution
        The stable root when exactly one of the two roots is stable, otherwise the root
        with the larger amplitude; the other root, if it exists, is in ``.other``.

    Examples
    --------
    A 1 kg, 1 Hz primary forced at 1.1 Hz with 1 N carries a 0.1 kg damper mass with
    0.125 m of free travel on each side:

    >>> import numpy as np
    >>> from impactpred.damper.masri_caughey import masri_caughey
    >>> s = masri_caughey(primary_mass=1.0, damper_mass=0.1, stiffness=(2 * np.pi)**2,
    ...                   force_amplitude=1.0, freq_hz=1.1, clearance=0.125, restitution=0.6)
    >>> s.exists, s.stable, round(s.amplitude, 5), round(s.impact_phase, 4), round(s.reduction, 3)
    (True, True, 0.05104, 3.3802, 0.423)
    >>> primary, damper = s.trajectory(np.linspace(0.0, 1 / 1.1, 5))
    """
    M = _check("primary_mass", primary_mass)
    m = _check("damper_mass", damper_mass)
    K = _check("stiffness", stiffness)
    F0 = _check("force_amplitude", force_amplitude)
    f = _check("freq_hz", freq_hz)
    cl = _check("clearance", clearance, strict=False)
    e = _check("restitution", restitution, strict=False, upper=1.0)
    inputs = {"primary_mass": M, "damper_mass": m, "stiffness": K, "force_amplitude": F0,
              "freq_hz": f, "clearance": cl, "restitution": e}
    xs = F0 / K
    wn = math.sqrt(K / M)
    r = 2 * np.pi * f / wn
    if r < MIN_FREQUENCY_RATIO:
        raise ValueError(f"freq_hz={f!r} is {r:.3g} times the primary's natural frequency "
                         f"({wn / (2 * np.pi):.4g} Hz): the symmetric motion is not solved "
                         f"below {MIN_FREQUENCY_RATIO:g} of it (the primary makes {1 / r:.3g} "
                         "free oscillations between impacts, each sampled by the check for an "
                         "intermediate contact); ImpactDamper.simulate runs such a forcing")
    mu = m / M
    c = cl / xs
    P = (1 - e) * (1 + mu) / (1 + e)
    nan = math.nan

    def none(note):
        return MasriCaugheySolution(**inputs, exists=False, stable=False, amplitude=nan,
                                    impact_phase=nan, damper_velocity=nan, primary_velocity=nan,
                                    impact_displacement=nan, notes=(note,))

    roots = _roots(mu, r, c, e)
    if not roots:
        return none("no real root: the forcing cannot sustain two impacts per cycle "
                    "(clearance too large for this frequency, mass ratio and restitution)")
    sols = []
    reasons = []
    for W, phi in roots:
        if not W < 0:
            reasons.append("a root has a non-positive approach velocity")
            continue
        x0, u, w = -c - 0.5 * np.pi * W, r * W * (P - mu), r * W
        if not _no_intermediate_contact(x0, u, w, phi, r, c):
            reasons.append("a root has an intermediate contact during the flight" + (
                " (with restitution 0 the mass leaves the stop at zero relative velocity: "
                "where the primary presses it, it sticks there, which this closed form "
                "does not model; ImpactDamper.simulate does)" if e == 0.0 else ""))
            continue
        amp = _amplitude(x0, u, phi, r)
        mult = _multipliers(mu, r, c, e, phi, x0, u, w, max(amp, c, 1e-300))
        rho = max(abs(z) for z in mult)
        stable = bool(rho < 1.0)
        if abs(rho - 1.0) < 1e-4:
            reasons.append(f"a root is marginally stable (largest multiplier {rho:.6f}): "
                           "the stability flag is not reliable")
        sols.append({"W": W, "phi": phi, "x0": x0, "u": u, "amp": amp, "mult": mult,
                     "stable": stable})
    if not sols:
        return none("; ".join(reasons))
    if len(sols) == 2 and sols[0]["stable"] != sols[1]["stable"]:
        sols.sort(key=lambda s: not s["stable"])
    else:
        sols.sort(key=lambda s: -s["amp"])

    def build(s, other, notes):
        return MasriCaugheySolution(
            **inputs, exists=True, stable=s["stable"], amplitude=float(s["amp"] * xs),
            impact_phase=float(s["phi"]), damper_velocity=float(-r * s["W"] * xs * wn),
            primary_velocity=float(r * s["W"] * (P + mu) * xs * wn),
            impact_displacement=float(s["x0"] * xs),
            multipliers=tuple(complex(z) for z in s["mult"]), other=other, notes=tuple(notes),
            _W=float(s["W"]))

    other = build(sols[1], None, ("second root",)) if len(sols) == 2 else None
    notes = reasons + (["two roots exist; the other is in .other"] if other is not None else [])
    return build(sols[0], other, notes)


def masri_caughey_curve(freq_hz, *, primary_mass, damper_mass, stiffness, force_amplitude,
                        clearance, restitution) -> pd.DataFrame:
    """:func:`masri_caughey` over an array of frequencies, as a DataFrame.

    Columns: ``freq_hz``, ``frequency_ratio``, ``exists``, ``stable``, ``amplitude``,
    ``amplitude_without_damper``, ``reduction``, ``impact_phase``, ``damper_velocity``,
    ``n_roots``, ``other_amplitude``, ``other_stable``.

    Parameters
    ----------
    freq_hz : array_like of float
        Forcing frequencies (Hz).
    primary_mass, damper_mass, stiffness, force_amplitude, clearance, restitution : float
        As in :func:`masri_caughey` (kg, N/m, N, m, -).

    Returns
    -------
    pandas.DataFrame
        One row per frequency, the columns above; a frequency below
        ``MIN_FREQUENCY_RATIO`` of the natural one is a row of NaN (``exists`` False), said
        once by a ``UserWarning``.
    """
    f = np.atleast_1d(np.asarray(freq_hz, dtype=float))
    if f.ndim != 1:
        raise ValueError(f"freq_hz must be a 1-D array, got shape {f.shape}")
    rows = []
    f_n = math.sqrt(as_positive_scalar("stiffness", stiffness)
                    / as_positive_scalar("primary_mass", primary_mass)) / (2 * np.pi)
    low = f < MIN_FREQUENCY_RATIO * f_n
    if np.any(low):
        warnings.warn(f"masri_caughey_curve: {int(np.count_nonzero(low))} frequencies below "
                      f"{MIN_FREQUENCY_RATIO:g} of the natural frequency are not solved "
                      "(rows of NaN, exists False)", UserWarning, stacklevel=2)
    for fi, skip in zip(f, low):
        if skip:
            nan = math.nan
            rows.append({"freq_hz": fi, "frequency_ratio": fi / f_n, "exists": False,
                         "stable": False, "amplitude": nan, "amplitude_without_damper": nan,
                         "reduction": nan, "impact_phase": nan, "damper_velocity": nan,
                         "n_roots": 0, "other_amplitude": nan, "other_stable": False})
            continue
        s = masri_caughey(primary_mass=primary_mass, damper_mass=damper_mass, stiffness=stiffness,
                          force_amplitude=force_amplitude, freq_hz=fi, clearance=clearance,
                          restitution=restitution)
        o = s.other
        rows.append({"freq_hz": fi, "frequency_ratio": s.frequency_ratio, "exists": s.exists,
                     "stable": s.stable, "amplitude": s.amplitude,
                     "amplitude_without_damper": s.amplitude_without_damper,
                     "reduction": s.reduction, "impact_phase": s.impact_phase,
                     "damper_velocity": s.damper_velocity,
                     "n_roots": 0 if not s.exists else 1 + (o is not None),
                     "other_amplitude": o.amplitude if o is not None else math.nan,
                     "other_stable": o.stable if o is not None else False})
    return pd.DataFrame(rows)
