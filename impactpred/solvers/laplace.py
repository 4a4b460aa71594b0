"""Exact, event-driven solver for rational receptances (the paper's Laplace method).

Each body is a real state-space realisation of its pole-residue receptance
(``ModalModel.to_statespace``). With ``X`` the stacked states of both bodies and the
contact force ``f`` acting as ``-f`` on body 1 and ``+f`` on body 2:

    X' = A X + Bf f,       g = g0 + Cg X + Dg f   (gap),  Dg = D1 + D2.

* Free flight: ``f = 0``, ``X(t) = expm(A t) X0``: closed form.
* Rigid contact: ``g = 0`` held. The force is a linear feedback ``f = Kf X + k0`` found
  from the first derivative of ``g`` in which ``f`` appears (relative degree 0: a
  flexibility term; 1; or 2: mass-like ``H ~ 1/s^2``). The stuck system
  ``X' = (A + Bf Kf) X`` has as poles the zeros of ``H1 + H2`` (paper eq. 5): its force
  is the inverse Laplace transform of ``(Y10 - Y20)/(H1 + H2)``. Where ``H1 + H2 ~ 1/s^2``
  and the bodies approach, the force has a Dirac impulse ``P = -g'/(Cg A Bf)`` at the
  contact's start, returned as such.
* Linear-spring contact (no damping): ``f = -k g`` while ``g < 0``: again linear.

Each phase is split once into its spectral form (:class:`._spectral.SpectralPhase`), so any
output is a closed-form sum of exponentials plus a polynomial. The free flight is split
block by block (the bodies are uncoupled); the contact phase is the free flight plus the
rank-one feedback ``Bf Kf``, so its poles are found as the zeros of the secular function
``1 - Kf (s - A)^-1 Bf`` (those of ``H1 + H2``) and its eigenvectors in closed form
(:mod:`._rank_one`: O(m^2) for the poles, O(n^2 m) for the eigenvectors, against the
general Schur route's O(n^3), which stays as the fallback). Events (separation where
``f`` crosses 0, contact where ``g`` crosses 0) are searched on that closed form every
``pi/(8 |lambda|max)`` (the fastest pole), with the dips between samples bounded by the
cubic Hermite interpolant and its error bound, and polished to rounding by safeguarded
Newton steps; the loop over phases runs compiled (:mod:`._event_loop`). No time-step
error anywhere: the output step only sets where the result is sampled. A phase matrix too
close to defective for an eigendecomposition falls back to matrix exponentials with the
same rules, in Python.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg
from scipy.optimize import brentq

from modalid._statespace import pole_residue_to_statespace

from ..contact import LinearSpring, Rigid
from ..result import BodyEnergy, ImpactResult
from ._event_loop import MAX_STALLS, contact_start, event_loop
from ._outputs import LaplaceOutputs
from ._spectral import DefectiveSpectrum, SpectralPhase

__all__ = ["solve_laplace", "CoupledSystem"]


class CoupledSystem:
    """The two bodies' stacked real state space and the bookkeeping of its states."""

    def __init__(self, bodies):
        blocks = []
        for body in bodies:
            m = body.modal_model()
            a, b, c, d = pole_residue_to_statespace(m.poles, m.residues, m.real_poles,
                                                    m.real_residues, m.inverse_mass,
                                                    m.flexibility)
            blocks.append((m, a, b, c, d))
        (m1, a1, b1, c1, d1), (m2, a2, b2, c2, d2) = blocks
        n1, n2 = a1.shape[0], a2.shape[0]
        self.n1, self.n = n1, n1 + n2
        self.models = (m1, m2)
        self.A = scipy.linalg.block_diag(a1, a2) if self.n else np.zeros((0, 0))
        self.Bf = np.concatenate([-b1, b2])
        self.C1 = np.concatenate([c1, np.zeros(n2)])
        self.C2 = np.concatenate([np.zeros(n1), c2])
        self.Cg = self.C2 - self.C1
        self.D = (d1, d2)
        self.Dg = d1 + d2
        self.X0 = np.concatenate([_initial_state(bodies[0], m1, n1),
                                  _initial_state(bodies[1], m2, n2)])

    def rigid_velocity(self, X, i):
        """Rigid-body velocity (m/s) of body ``i`` in state ``X`` (0 if grounded)."""
        m = self.models[i]
        if not m.inverse_mass:
            return 0.0
        end = self.n1 if i == 0 else self.n
        return float(X[end - 1])

    def energies(self, X, f):
        """(rigid, vibration) energy (J) of each body in state ``X`` with force ``f``."""
        out = []
        for i, m in enumerate(self.models):
            offset = 0 if i == 0 else self.n1
            z = X[offset:offset + 2 * m.n_modes:2] + 1j * X[offset + 1:offset + 2 * m.n_modes:2]
            with np.errstate(divide="ignore"):   # a zero residue: no energy in that mode
                modal_mass = -1.0 / (2.0 * m.poles.imag * m.residues.imag)
            vib = float(np.sum(np.abs(z) ** 2 / (2.0 * modal_mass))) + 0.5 * self.D[i] * f**2
            u = self.rigid_velocity(X, i)
            rigid = 0.5 * u**2 / m.inverse_mass if m.inverse_mass else 0.0
            out.append((rigid, vib))
        return out


def _initial_state(body, model, n):
    x = np.zeros(n)
    states = body.initial_modal_states()
    if states is not None:
        order = np.argsort(np.abs(model.poles), kind="stable")[:body.vibration.shape[0]]
        z0 = states[2]
        x[2 * order] = z0.real
        x[2 * order + 1] = z0.imag
    if model.inverse_mass:
        x[n - 2] = body.displacement
        x[n - 1] = body.velocity
    return x


def _relative_degree(sysm: CoupledSystem):
    """(rho, coefficient) of the first derivative of the gap in which ``f`` appears."""
    # the fastest rate of the free bodies: their poles (A is their modal realisation)
    rates = [np.abs(np.concatenate([m.poles, m.real_poles])) for m in sysm.models]
    scale = max([1.0] + [float(r.max()) for r in rates if r.size])
    c0 = sysm.Dg
    c1 = float(sysm.Cg @ sysm.Bf) if sysm.n else 0.0
    c2 = float(sysm.Cg @ sysm.A @ sysm.Bf) if sysm.n else 0.0
    ref = abs(c2) + abs(c1) * scale + abs(c0) * scale**2
    if ref == 0.0:
        raise ValueError("H1 + H2 is identically zero: the bodies have no compliance")
    if abs(c0) * scale**2 > 1e-12 * ref:
        return 0, c0
    if abs(c1) * scale > 1e-12 * ref:
        return 1, c1
    return 2, c2


class _ExpmForm:
    """Fallback with :class:`SpectralPhase`'s interface, by matrix exponentials.

    Used when the phase matrix is too close to defective for an eigendecomposition.
    """

    def __init__(self, M):
        self.M = M
        self.max_rate = float(np.max(np.abs(np.linalg.eigvals(M)))) if M.size else 0.0

    def coordinates(self, x):
        return x

    def output_coefficients(self, rows, coords):
        return np.atleast_2d(rows), coords

    def evaluate(self, coefficients, taus, derivative=0):
        rows, x = coefficients
        M_d = np.linalg.matrix_power(self.M, derivative)
        cols = [M_d @ (scipy.linalg.expm(self.M * tau) @ x) for tau in np.atleast_1d(taus)]
        return rows @ np.array(cols).T

    def evaluate_orders(self, coefficients, taus, derivatives=(0, 1)):
        return [self.evaluate(coefficients, taus, d) for d in derivatives]

    def scalar(self, coefficients, tau, derivative=0):
        return float(self.evaluate(coefficients, [tau], derivative)[0, 0])

    def state(self, coords, tau):
        return scipy.linalg.expm(self.M * tau) @ coords


def _phase_form(M, update_of=None):
    if update_of is not None and not isinstance(update_of[0], SpectralPhase):
        update_of = None
    try:
        return SpectralPhase(M, update_of=update_of)
    except DefectiveSpectrum:
        return _ExpmForm(M)


class _Phase:
    """One kind of phase (free flight or stuck contact): its propagator and its rows.

    ``update_of=(free_form, b, r)``: ``M`` is the free flight's matrix plus ``outer(b, r)``
    (the contact force fed back), split through the free flight's form.
    """

    def __init__(self, M, rows, event_row, contact, *, update_of=None):
        self.form = _phase_form(M, update_of)
        self.M = M
        self.rows = rows            # force, y1, y2, gap (4 x n_aug)
        self.event_row = event_row  # event when it turns negative
        self.contact = contact

    def kernel_data(self, t_end):
        """The phase as :func:`._event_loop.event_loop` takes it (spectral form only).

        Its event search step resolves its own fastest pole: ``pi/(8 |lambda|max)``.

        Its output rows leave out the gap (row 3): it is ``y2 - y1 + gap0`` by definition
        (the flexibility terms included), so the caller forms it from the samples.
        """
        f = self.form
        poly_o, expo_o = f.project(np.delete(self.rows, 3, axis=0))
        poly_e, expo_e = f.project(self.event_row)
        return (f.rates, f._modes.real.copy(), f._modes.imag.copy(), f._proj.real.copy(),
                f._proj.imag.copy(), f.in0, f._s0_powers, poly_o, expo_o, poly_e, expo_e,
                np.asarray(self.event_row, dtype=float), _search_step(f.max_rate, t_end))


def solve_laplace(bodies, gap0, contact, t_end, dt, *, notes=()):
    """Exact event-driven solve of two rational bodies; see the module docstring."""
    if any(b.load is not None for b in bodies):
        raise ValueError("the laplace solver takes no external load: use method='modal'")
    sysm = CoupledSystem(bodies)
    points = LaplaceOutputs(bodies, sysm)
    n = sysm.n
    A, Bf, Cg = sysm.A, sysm.Bf, sysm.Cg
    D1, D2 = sysm.D
    n_aug = n + 2  # [X, 1, J]
    one, jdx = n, n + 1

    def aug(row_x, const=0.0):
        row = np.zeros(n_aug)
        row[:n] = row_x
        row[one] = const
        return row

    gap_row = aug(Cg, gap0)
    y1_row, y2_row = aug(sysm.C1), aug(sysm.C2)

    # free flight: X' = A X
    M_free = np.zeros((n_aug, n_aug))
    M_free[:n, :n] = A
    free = _Phase(M_free, np.vstack([np.zeros(n_aug), y1_row, y2_row, gap_row,
                                     points.rows(M_free)]), gap_row, False)

    # contact: f = Kf X + k0, X' = (A + Bf Kf) X + Bf k0, J' = f
    if isinstance(contact, Rigid):
        rho, coef = _relative_degree(sysm)
        if rho == 0:
            kf, k0 = -Cg / coef, -gap0 / coef
        elif rho == 1:
            kf, k0 = -(Cg @ A) / coef, 0.0
        else:
            kf, k0 = -(Cg @ A @ A) / coef, 0.0
    elif isinstance(contact, LinearSpring) and contact.damping == 0.0:
        rho, coef = None, None
        k = contact.stiffness
        kf, k0 = -k * Cg / (1 + k * sysm.Dg), -k * gap0 / (1 + k * sysm.Dg)
    else:
        raise ValueError(f"the laplace solver takes Rigid() or an undamped LinearSpring, got "
                         f"{contact!r}: use method='modal' or 'convolution'")
    force_row = aug(kf, k0)
    # the force enters the states through Bf and its integral J: a rank-one update
    force_in = np.concatenate([Bf, [0.0, 1.0]])
    M_con = M_free + np.outer(force_in, force_row)
    stuck = _Phase(M_con, np.vstack([force_row, y1_row - D1 * force_row,
                                     y2_row + D2 * force_row,
                                     gap_row + sysm.Dg * force_row,
                                     points.rows(M_con, force_row)]), force_row, True,
                   update_of=(free.form, force_in, force_row))

    step = _search_step(max(free.form.max_rate, stuck.form.max_rate), t_end)
    out_step = dt if dt is not None else t_end / 4000

    Xa = np.concatenate([sysm.X0, [1.0, 0.0]])
    u_scale = max(abs(b.velocity) for b in bodies)
    y_scale = abs(gap0) + u_scale * t_end + float(np.max(np.abs(sysm.X0), initial=0.0))
    tol_g = 1e-12 * max(y_scale, 1e-300)

    samples = []          # (times, 4 x k values) blocks
    intervals, diracs = [], []
    phase_log = []        # (phase, t0, coords) of every contact phase, for the exact peak

    def gap_rate(X):
        return float(Cg @ (A @ X[:n])) if n else 0.0

    # the contact rules (Dirac impulse, hold or release), shared with the compiled loop
    rho_code, coef_value = (-1, 1.0) if rho is None else (rho, float(coef))
    force_rate_row = force_row @ M_con
    cg_powers = np.zeros((3, n))
    if n:
        cg_powers[0] = Cg @ A
        cg_powers[1] = cg_powers[0] @ A
        cg_powers[2] = cg_powers[1] @ A

    def start_contact(t, Xa):
        """Apply any Dirac impulse; return (Xa, holds) with holds False if f < 0 at once."""
        Xa = Xa.copy()
        impulse, holds = contact_start(Xa, rho_code, coef_value, Bf, jdx, force_row,
                                       force_rate_row, cg_powers, step, tol_g)
        if impulse != 0.0:
            diracs.append((t, impulse))
        return Xa, bool(holds)

    def emit(phase, coeffs, t0, t_from, t_to, inclusive_end):
        """Output samples of ``phase`` on the output grid in (t_from, t_to)."""
        k_lo = int(math.floor(t_from / out_step + 1e-9)) + 1
        k_hi = int(math.ceil(t_to / out_step - 1e-9)) - 1
        grid = out_step * np.arange(k_lo, k_hi + 1) if k_hi >= k_lo else np.zeros(0)
        grid = grid[(grid > t_from) & (grid < t_to)]
        times = np.concatenate([grid, [t_to]]) if inclusive_end else grid
        if times.size:
            samples.append((times, phase.form.evaluate(coeffs, times - t0)))

    def run_phase(phase, t0, Xa):
        """Propagate from (t0, Xa) to the phase's first event or t_end.

        Contact: the event is the force turning negative. Free flight: the gap turning
        negative beyond rounding (``tol_g``); if it is not positive at the start of a
        search step, the contact starts there. The event function is evaluated on
        chunks of search steps at once and its root polished by Brent's method on the
        closed form.
        """
        form = phase.form
        coords = form.coordinates(Xa)
        out_coeffs = form.output_coefficients(phase.rows, coords)
        ev_coeffs = form.output_coefficients(phase.event_row, coords)
        if phase.contact and not phase_log:
            phase_log.append((phase, t0, coords))
        samples.append((np.array([t0]), form.evaluate(out_coeffs, [0.0])))
        threshold = 0.0 if phase.contact else -tol_g

        def event(x):
            return form.scalar(ev_coeffs, x)

        def rate(x):
            return form.scalar(ev_coeffs, x, derivative=1)

        tau, e_prev, chunk = 0.0, float(phase.event_row @ Xa), 32
        de_prev = rate(0.0)
        while t0 + tau < t_end * (1 - 1e-15):
            taus = tau + step * np.arange(1, chunk + 1)
            if t0 + taus[-1] >= t_end:  # the last chunk ends exactly at t_end
                taus = np.append(taus[t0 + taus < t_end], t_end - t0)
            e, de = (row[0] for row in form.evaluate_orders(ev_coeffs, taus, (0, 1)))
            # a dip between samples (falling, then rising) may cross and come back: find
            # its minimum exactly and, if it crosses, cut the samples there
            starts = np.concatenate([[tau], taus[:-1]])
            e_starts = np.concatenate([[e_prev], e[:-1]])
            de_starts = np.concatenate([[de_prev], de[:-1]])
            dips = np.flatnonzero((de_starts < 0) & (de > 0) & (e_starts >= threshold)
                                  & (e >= threshold))
            for d in dips:
                t_min = brentq(rate, starts[d], taus[d], xtol=1e-15 * max(taus[d], 1e-300))
                if event(t_min) < threshold:
                    taus, e = np.append(taus[:d], t_min), np.append(e[:d], event(t_min))
                    break
            crossed = e < threshold
            if np.any(crossed):
                i = int(np.argmax(crossed))
                a, b = (taus[i - 1] if i else tau), taus[i]
                e_a = e[i - 1] if i else e_prev
                # rounding-level values count as zero
                zero_tol = tol_g if not phase.contact else 1e-12 * float(np.max(np.abs(e)))
                if e_a <= zero_tol and a == 0.0:
                    # the phase starts at an event (e = 0): the event function may open a
                    # short positive lobe before it turns negative; look for it
                    fine = np.geomspace(b * 1e-9, b, 256)
                    e_fine = form.evaluate(ev_coeffs, fine)[0]
                    positive = np.flatnonzero(e_fine > zero_tol)
                    if positive.size and np.any(e_fine[positive[0]:] < threshold):
                        j = positive[0] + int(np.argmax(e_fine[positive[0]:] < threshold))
                        a, b, e_a = fine[j - 1], fine[j], e_fine[j - 1]
                if e_a <= zero_tol:
                    root = a
                else:
                    root = brentq(event, a, b, xtol=1e-15 * max(b, 1e-300),
                                  rtol=4 * np.finfo(float).eps)
                emit(phase, out_coeffs, t0, t0, t0 + root, True)
                return t0 + root, form.state(coords, root), True
            tau, e_prev, de_prev = float(taus[-1]), float(e[-1]), float(de[-1])
            chunk = min(2 * chunk, 4096)
        emit(phase, out_coeffs, t0, t0, t_end, True)
        return t_end, form.state(coords, t_end - t0), False

    t = 0.0
    # touching at t = 0 and approaching: the first contact starts at once
    in_contact = bool(n) and gap0 <= tol_g and gap_rate(Xa) < 0
    if all(isinstance(p.form, SpectralPhase) for p in (free, stuck)):
        (status, t_stall, T, V, iv, dv, Xa, first_impulse, first_t0,
         first_x) = event_loop(free.kernel_data(t_end), stuck.kernel_data(t_end), Xa,
                               in_contact, t_end, step, out_step, tol_g, rho_code,
                               coef_value, Bf, jdx, force_row, force_rate_row, cg_powers,
                               float(gap0))
        if status:
            raise _grazing(t_stall)
        intervals = [tuple(r) for r in iv.tolist()]
        diracs = [tuple(r) for r in dv.tolist()]
        first_impulse = float(first_impulse)
        if first_t0 >= 0.0:
            phase_log.append((stuck, first_t0, stuck.form.coordinates(first_x)))
        return _result(bodies, sysm, points, T, V, intervals, diracs, phase_log, Xa,
                       first_impulse, force_row, jdx, t_end, out_step, step, "spectral",
                       notes)
    contact_at = 0.0
    first_impulse = None
    if in_contact:
        Xa, in_contact = start_contact(0.0, Xa)
        if not in_contact:
            intervals.append((0.0, 0.0))
    stalled = 0
    while t < t_end * (1 - 1e-15):
        t_ev, Xa, happened = run_phase(stuck if in_contact else free, t, Xa)
        stalled = stalled + 1 if t_ev == t else 0
        if stalled > MAX_STALLS:
            raise _grazing(t)
        t = t_ev
        if not happened:
            break
        if in_contact:  # separation
            intervals.append((contact_at, t))
            in_contact = False
        else:  # contact
            contact_at = t
            Xa, in_contact = start_contact(t, Xa)
            if not in_contact:
                intervals.append((t, t))
        if first_impulse is None and intervals:
            first_impulse = float(Xa[jdx])
    if in_contact:
        intervals.append((contact_at, t_end))
    if first_impulse is None:
        first_impulse = float(Xa[jdx])

    T = np.concatenate([blk[0] for blk in samples])
    V = np.concatenate([blk[1] for blk in samples], axis=1)
    return _result(bodies, sysm, points, T, V, intervals, diracs, phase_log, Xa,
                   first_impulse, force_row, jdx, t_end, out_step, step,
                   "matrix-exponential", notes)


def _search_step(rate, t_end):
    """Event-search step (s) resolving the fastest pole ``rate`` (rad/s): ``pi/(8 rate)``."""
    return min(np.pi / (8 * rate) if rate > 0 else t_end / 1000, t_end / 20)


def _grazing(t):
    return RuntimeError(f"contact events repeat without time advancing at t = {t!r} s: the "
                        "contact state cannot be decided (grazing); use method='modal'")


def _result(bodies, sysm, points, T, V, intervals, diracs, phase_log, X_end, first_impulse,
            force_row, jdx, t_end, out_step, step, kind, notes):
    """The :class:`ImpactResult` of the samples and events of either event loop."""
    n = sysm.n
    T, V = _insert_exact_peak(T, V, intervals, phase_log)
    F = np.maximum(V[0], 0.0)
    in_contact_end = bool(intervals) and intervals[-1][1] == t_end and intervals[-1][0] < t_end
    f_end = float(force_row @ X_end) if in_contact_end else 0.0
    u_before = (bodies[0].velocity, bodies[1].velocity)
    u_after = (sysm.rigid_velocity(X_end[:n], 0), sysm.rigid_velocity(X_end[:n], 1))
    before = sysm.energies(sysm.X0, 0.0)
    after = sysm.energies(X_end[:n], f_end)
    energy = tuple(BodyEnergy(b[0], b[1], a[0], a[1]) for b, a in zip(before, after))
    inv = (bodies[0].inverse_mass, bodies[1].inverse_mass)
    note = (f"exact (Laplace/state-space, {kind}) solution; output step {out_step:.4g} s, "
            f"event search step {step:.4g} s",)
    return ImpactResult(t=T, force=F, y1=V[1], y2=V[2], gap=V[3],
                        contact_intervals=tuple(intervals), dirac_impulses=tuple(diracs),
                        velocities_before=u_before, velocities_after=u_after,
                        energy_by_body=energy, method="laplace", dt=out_step,
                        first_contact_impulse=first_impulse,
                        total_impulse=float(X_end[jdx]), inverse_masses=inv,
                        notes=tuple(notes) + note,
                        points=points.responses(bodies, T, V[4:]))


def _insert_exact_peak(T, V, intervals, phase_log):
    """Insert the exact maximum of the first contact's force (a root of ``f'``) as a sample."""
    if not intervals or intervals[0][1] <= intervals[0][0] or not phase_log:
        return T, V
    start, end = intervals[0]
    phase, t0, coords = phase_log[0]
    inside = np.flatnonzero((T > start) & (T < end))
    if inside.size < 1:
        return T, V
    i = inside[np.argmax(V[0, inside])]
    form = phase.form
    coeffs = form.output_coefficients(phase.event_row, coords)

    def rate(x):
        return form.evaluate(coeffs, [x - t0], derivative=1)[0, 0]

    lo, hi = (T[i - 1] if i > 0 else start), (T[i + 1] if i + 1 < T.size else end)
    lo, hi = max(lo, start), min(hi, end)
    for a, b in ((lo, T[i]), (T[i], hi)):
        if b > a and rate(a) > 0 >= rate(b):
            t_peak = brentq(rate, a, b, xtol=1e-15 * max(b, 1e-300))
            values = form.evaluate(form.output_coefficients(phase.rows, coords), [t_peak - t0])
            k = int(np.searchsorted(T, t_peak))
            T_out, V_out = np.empty(T.size + 1), np.empty((V.shape[0], T.size + 1))
            T_out[:k], T_out[k], T_out[k + 1:] = T[:k], t_peak, T[k:]
            V_out[:, :k], V_out[:, k], V_out[:, k + 1:] = V[:, :k], values[:, 0], V[:, k:]
            return T_out, V_out
    return T, V
