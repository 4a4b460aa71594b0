"""The exact engine's run of one contact with one clearance (``solve_impact``'s Laplace
method): free flight and contact phases in closed form, events found on the closed form.

The front end (:mod:`impactpred.solvers.laplace`) builds the two phases (:class:`Phase`:
the phase matrix on the augmented state ``[X, 1, J]``, its output rows and its event row)
and the contact rules' data; :func:`run_contact` runs them from ``t = 0`` to ``t_end``:

* free flight ends where the gap turns negative beyond rounding (``tol_g``), contact where
  the force turns negative;
* at a contact start the rules of :func:`impactpred.engine.contact_loop.contact_start`
  apply (a Dirac impulse where the gap has relative degree 2, then hold or release);
* the phases' spectral forms (:class:`impactpred.engine.spectral.SpectralPhase`) run in
  the compiled loop (:func:`impactpred.engine.contact_loop.event_loop`); a phase matrix
  too close to defective falls back to matrix exponentials (:class:`ExpmForm`) and the
  same rules in Python (events bracketed on chunks of search steps, dips between samples
  located, roots polished by Brent's method on the closed form).

Times in s, states in the bodies' modal units, forces in N, impulses in N s.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg
from scipy.optimize import brentq

from .contact_loop import MAX_STALLS, MIN_ADVANCE, contact_start, event_loop
from .spectral import DefectiveSpectrum, SpectralPhase

__all__ = ["Phase", "ExpmForm", "ContactRules", "RawRun", "run_contact", "search_step",
           "grazing_error", "insert_exact_peak"]


#: :class:`ExpmForm` keeps this many exponentials of a span, and last states
_KEPT_STEPS = 8


class ExpmForm:
    """Fallback with :class:`SpectralPhase`'s interface, by matrix exponentials.

    Used when the phase matrix is too close to defective for an eigendecomposition.
    """

    def __init__(self, M):
        self.M = M
        self.max_rate = float(np.max(np.abs(np.linalg.eigvals(M)))) if M.size else 0.0
        # e^(M h) by h, and the last state reached from each start (its coordinates'
        # bytes): the event search evaluates chunks of evenly spaced times, each starting
        # where the last ended, so a chunk costs matrix-vector products, not an expm per
        # time (a 463-state contact phase of a rod on a cantilever: hours -> seconds)
        self._steps, self._last = {}, {}

    def coordinates(self, x):
        return x

    def output_coefficients(self, rows, coords):
        return np.atleast_2d(rows), coords

    def project(self, rows):
        return np.atleast_2d(rows)

    def product_integrals(self, projected, runs, pairs):
        """:meth:`SpectralPhase.product_integrals` by scaling and squaring: with ``E(t) =
        e^(M t)`` and ``W(t) = int_0^t E' Q E`` (``Q = outer(rows[a], rows[b])``),
        ``W(2t) = W(t) + E(t)' W(t) E(t)``, from ``t = h / 2^N`` short enough (a tenth of
        the fastest rate's time) for Van Loan's block exponential of ``[[-M', Q], [0,
        M]]``, whose ``e^(-M' t)`` would overflow over a stiff pole's whole run."""
        rows, n = np.atleast_2d(projected), self.M.shape[0]
        total = np.zeros(len(pairs))
        for x0, h in runs:
            squarings = max(0, math.ceil(math.log2(max(h * self.max_rate, 1e-300) / 0.1)))
            t = h / 2.0 ** squarings
            for i, (a, b) in enumerate(pairs):
                block = np.zeros((2 * n, 2 * n))
                block[:n, :n], block[:n, n:] = -self.M.T, np.outer(rows[a], rows[b])
                block[n:, n:] = self.M
                e = scipy.linalg.expm(block * t)
                step, w = e[n:, n:], e[n:, n:].T @ e[:n, n:]
                for _ in range(squarings):
                    w = w + step.T @ w @ step
                    step = step @ step
                total[i] += float(x0 @ w @ x0)
        return total

    def _step(self, h):
        """``e^(M h)``, kept for the last :data:`_KEPT_STEPS` spans ``h`` asked for (spans
        equal to 13 digits share one: ``tau + k step`` rounds each span differently)."""
        key = float(f"{h:.13g}")
        if key not in self._steps:
            if len(self._steps) >= _KEPT_STEPS:
                self._steps.pop(next(iter(self._steps)))
            self._steps[key] = scipy.linalg.expm(self.M * key)
        return self._steps[key]

    def states(self, x, taus):
        """``e^(M tau) x`` at each of ``taus`` (ascending, s), as columns, shape ``(n,
        len(taus))``: from the last state reached from ``x`` at or before a time, or from
        ``x``, by the exponential of the span (kept: spans repeat), so evenly spaced times
        cost one product each. A single time is always taken from ``x`` itself: a root
        finder's values then do not depend on the order it asks for them (from the last
        state they rounded differently, and Brent's bracket lost its sign change)."""
        taus = np.atleast_1d(np.asarray(taus, float))
        x = np.asarray(x, float)
        if taus.size == 1:
            return (scipy.linalg.expm(self.M * taus[0]) @ x)[:, None]
        key = x.tobytes()
        t_prev, s_prev = self._last.get(key, (0.0, x))
        out = np.empty((x.shape[0], taus.size))
        for k, tau in enumerate(taus):
            if tau < t_prev:                          # before the last state: from x
                t_prev, s_prev = 0.0, x
            if tau != t_prev:
                s_prev = self._step(tau - t_prev) @ s_prev
                t_prev = tau
            out[:, k] = s_prev
        if len(self._last) >= _KEPT_STEPS:
            self._last.pop(next(iter(self._last)))
        self._last[key] = (t_prev, s_prev)
        return out

    def evaluate(self, coefficients, taus, derivative=0):
        return self.evaluate_orders(coefficients, taus, (derivative,))[0]

    def evaluate_orders(self, coefficients, taus, derivatives=(0, 1)):
        rows, x = coefficients
        taus = np.atleast_1d(np.asarray(taus, float))
        order = np.argsort(taus, kind="stable")
        states = np.empty((self.M.shape[0], taus.size))
        states[:, order] = self.states(x, taus[order])
        return [rows @ (np.linalg.matrix_power(self.M, d) @ states) for d in derivatives]

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
        return ExpmForm(M)


class Phase:
    """One kind of phase (free flight or stuck contact): its propagator and its rows.

    ``update_of=(free_form, b, r)``: ``M`` is the free flight's matrix plus ``outer(b, r)``
    (the contact force fed back), split through the free flight's form.
    """

    def __init__(self, M, rows, event_row, contact, *, update_of=None):
        self.form = _phase_form(M, update_of)
        self.M = M
        self.rows = rows            # force, y1, y2, gap, v1, v2, output points (x n_aug)
        self.event_row = event_row  # event when it turns negative
        self.contact = contact

    def kernel_data(self, t_end):
        """The phase as :func:`.contact_loop.event_loop` takes it (spectral form only).

        The certified search (:func:`.search.first_event`) takes the rates' moduli,
        their fourth powers and their order, fastest first.

        Its output rows leave out the gap (row 3): it is ``y2 - y1 + gap0`` by definition
        (the flexibility terms included), so the caller forms it from the samples.
        Entry 11 is ``|event row| @ |modes|`` (m,), the rounding scale of the event row's
        projections (see :func:`.contact_loop.phase_run`).
        """
        f = self.form
        poly_o, expo_o = f.project(np.delete(self.rows, 3, axis=0))
        poly_e, expo_e = f.project(self.event_row)
        ev_abs = np.abs(np.asarray(self.event_row, dtype=float)) @ np.abs(f._modes)
        return (f.rates, f._modes.real.copy(), f._modes.imag.copy(), f._proj.real.copy(),
                f._proj.imag.copy(), f.in0, f._s0_powers, poly_o, expo_o, poly_e, expo_e,
                ev_abs, *_search_terms(f.rates))


class ContactRules:
    """The data of the contact-start rules (:func:`.contact_loop.contact_start`).

    ``rho``: relative degree of the gap w.r.t. the force (0, 1, 2; -1 for a spring law),
    ``coef`` its coefficient; ``bf`` the force's input vector (shape (n,)), ``jdx`` the
    index of the impulse integral ``J`` in the augmented state; ``force_row``,
    ``force_rate_row`` the force and its rate in the contact phase (rows on the augmented
    state ``[X, 1, J, cos, sin of each load]``);
    ``cg_powers`` (3, n + 2 + ...): the gap's first three derivatives in free flight as
    rows on the augmented state; ``tol_g`` (m) the gap's rounding level.
    """

    __slots__ = ("rho", "coef", "bf", "jdx", "force_row", "force_rate_row", "cg_powers",
                 "tol_g")

    def __init__(self, rho, coef, bf, jdx, force_row, force_rate_row, cg_powers, tol_g):
        self.rho, self.coef, self.bf, self.jdx = int(rho), float(coef), bf, int(jdx)
        self.force_row, self.force_rate_row = force_row, force_rate_row
        self.cg_powers, self.tol_g = cg_powers, float(tol_g)

    def start(self, xa, step):
        """Apply any Dirac impulse to ``xa`` in place; ``(impulse, holds)``."""
        impulse, holds = contact_start(xa, self.rho, self.coef, self.bf, self.jdx,
                                       self.force_row, self.force_rate_row, self.cg_powers,
                                       step, self.tol_g)
        return float(impulse), bool(holds)


class RawRun:
    """What :func:`run_contact` returns: samples ``T`` (s), ``V`` (rows x len(T)), the
    contact intervals and Dirac impulses ``(t, P)``, every phase ``(phase, t0, t1, x0)``
    in order (its :class:`Phase`, start and end times, augmented state at the start, a
    contact's Dirac impulse applied), the final augmented state, the impulse of the first
    contact, and which propagation ran (``"spectral"`` or ``"matrix-exponential"``)."""

    __slots__ = ("T", "V", "intervals", "diracs", "phases", "x_end", "first_impulse",
                 "kind")

    def __init__(self, T, V, intervals, diracs, phases, x_end, first_impulse, kind):
        self.T, self.V, self.intervals, self.diracs = T, V, intervals, diracs
        self.phases, self.x_end = phases, x_end
        self.first_impulse, self.kind = first_impulse, kind

    @property
    def first_phase(self):
        """The first contact phase as ``(phase, t0, coords)`` (its spectral coordinates at
        the start), or None without one."""
        for phase, t0, _t1, x0 in self.phases:
            if phase.contact:
                return phase, t0, phase.form.coordinates(x0)
        return None


def _phase_list(free, stuck, starts, states, t_end):
    """``[(phase, t0, t1, x0), ...]`` from the phases' start times, kinds and states."""
    ends = [t0 for t0, _ in starts[1:]] + [t_end]
    return [(stuck if contact else free, t0, end, x0)
            for (t0, contact), end, x0 in zip(starts, ends, states)]


def _root(f, a, b, *, rising=False):
    """Where ``f`` changes sign in ``[a, b]`` (falling through 0, or ``rising``) to
    ``1e-15`` of ``b``: Brent's method, allowed the iterations its worst case needs (near a
    tangency, a root 1e-11 s into a search step whose start is zero to rounding took 102,
    past scipy's default 100).

    The bracket comes from values evaluated on a grid, which round differently from
    ``f`` alone; where ``f`` itself shows no sign change the values are at rounding level
    (a gap of 1e-21 m 2e-10 s into a phase): the change is at ``a`` if ``f(a)`` already
    has the sign it changes to, else at ``b``."""
    def changed(v):
        return v >= 0.0 if rising else v <= 0.0

    if changed(f(a)):
        return a
    if not changed(f(b)):
        return b
    return brentq(f, a, b, xtol=1e-15 * max(b, 1e-300), rtol=4 * np.finfo(float).eps,
                  maxiter=5000)


def run_contact(free, stuck, xa, *, in_contact, rules, t_end, step, out_step, gap0):
    """Run the free-flight and contact phases from ``t = 0`` (state ``xa``) to ``t_end``.

    ``in_contact``: the contact rules decide at ``t = 0`` (touching, not separating); ``step``
    (s): the event search step; ``out_step`` (s): the output grid. Raises
    ``RuntimeError`` (:func:`grazing_error`) where events repeat without time advancing.
    """
    tol_g, jdx = rules.tol_g, rules.jdx
    if all(isinstance(p.form, SpectralPhase) for p in (free, stuck)):
        (status, t_stall, T, V, iv, dv, x_end, first_impulse, starts,
         states) = event_loop(free.kernel_data(t_end), stuck.kernel_data(t_end), xa,
                               in_contact, t_end, step, out_step, tol_g, rules.rho,
                               rules.coef, rules.bf, jdx, rules.force_row,
                               rules.force_rate_row, rules.cg_powers, float(gap0))
        if status:
            raise grazing_error(t_stall)
        phases = _phase_list(free, stuck, [(float(t0), bool(c)) for t0, c in starts],
                             list(states.T), t_end)
        return RawRun(T, V, [tuple(r) for r in iv.tolist()],
                      [tuple(r) for r in dv.tolist()], phases, x_end, float(first_impulse),
                      "spectral")

    samples = []          # (times, rows x k values) blocks
    intervals, diracs = [], []
    phase_starts, phase_states = [], []     # every phase's (t0, contact), starting state

    def start_contact(t, Xa):
        """Apply any Dirac impulse; return (Xa, holds) with holds False if f < 0 at once."""
        Xa = Xa.copy()
        impulse, holds = rules.start(Xa, step)
        if impulse != 0.0:
            diracs.append((t, impulse))
        return Xa, holds

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
        phase_starts.append((t0, phase.contact))
        phase_states.append(Xa.copy())
        samples.append((np.array([t0]), form.evaluate(out_coeffs, [0.0])))
        # the gap's rounding level: the caller's, or that of the gap's own size over the
        # first chunk of steps (a run from rest under a load has no initial displacement
        # to scale it by: 1e-312 let a dip of -5e-35 m 2e-18 s into the phase, the
        # rounding of a plastic impulse's zero velocity, start a contact again at once)
        gap_tol = tol_g
        threshold = 0.0 if phase.contact else -gap_tol

        def event(x):
            return form.scalar(ev_coeffs, x)

        def rate(x):
            return form.scalar(ev_coeffs, x, derivative=1)

        # the start's value as every later one is evaluated (``row @ Xa`` rounds
        # differently: +1e-20 against -5e-20 at a gap that is 0, and the root's
        # bracket then had one sign)
        tau, e_prev, chunk = 0.0, event(0.0), 32
        de_prev = rate(0.0)
        while t0 + tau < t_end * (1 - 1e-15):
            taus = tau + step * np.arange(1, chunk + 1)
            if t0 + taus[-1] >= t_end:  # the last chunk ends exactly at t_end
                taus = np.append(taus[t0 + taus < t_end], t_end - t0)
            e, de = (row[0] for row in form.evaluate_orders(ev_coeffs, taus, (0, 1)))
            if tau == 0.0 and not phase.contact:
                gap_tol = max(tol_g, 4.0 * np.finfo(float).eps * float(np.max(np.abs(e))))
                threshold = -gap_tol
            # a dip between samples (falling, then rising) may cross and come back: find
            # its minimum exactly and, if it crosses, cut the samples there
            starts = np.concatenate([[tau], taus[:-1]])
            e_starts = np.concatenate([[e_prev], e[:-1]])
            de_starts = np.concatenate([[de_prev], de[:-1]])
            dips = np.flatnonzero((de_starts < 0) & (de > 0) & (e_starts >= threshold)
                                  & (e >= threshold))
            for d in dips:
                t_min = _root(rate, starts[d], taus[d], rising=True)
                if event(t_min) < threshold:
                    taus, e = np.append(taus[:d], t_min), np.append(e[:d], event(t_min))
                    break
            crossed = e < threshold
            if np.any(crossed):
                i = int(np.argmax(crossed))
                a, b = (taus[i - 1] if i else tau), taus[i]
                e_a = e[i - 1] if i else e_prev
                # rounding-level values count as zero
                zero_tol = gap_tol if not phase.contact else 1e-12 * float(np.max(np.abs(e)))
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
                    root = _root(event, a, b)
                emit(phase, out_coeffs, t0, t0, t0 + root, True)
                return t0 + root, form.state(coords, root), True
            tau, e_prev, de_prev = float(taus[-1]), float(e[-1]), float(de[-1])
            chunk = min(2 * chunk, 4096)
        emit(phase, out_coeffs, t0, t0, t_end, True)
        return t_end, form.state(coords, t_end - t0), False

    t = 0.0
    Xa = xa
    contact_at = 0.0
    first_impulse = None
    if in_contact:
        n_diracs = len(diracs)
        Xa, in_contact = start_contact(0.0, Xa)
        if not in_contact and len(diracs) > n_diracs:   # a Dirac alone: over at once
            intervals.append((0.0, 0.0))
            first_impulse = float(Xa[jdx])
    stalled = 0
    while t < t_end * (1 - 1e-15):
        t_ev, Xa, happened = run_phase(stuck if in_contact else free, t, Xa)
        stalled = stalled + 1 if t_ev - t <= MIN_ADVANCE * t_end else 0
        if stalled > MAX_STALLS:
            raise grazing_error(t)
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
    phases = _phase_list(free, stuck, phase_starts, phase_states, t_end)
    return RawRun(T, V, intervals, diracs, phases, Xa, first_impulse, "matrix-exponential")


def _search_terms(rates):
    """``(|rates|, |rates|^4, order fastest first)`` as :func:`.search.first_event` takes
    them (the order as :class:`.phase.PhaseKind`'s ``order_desc``)."""
    abs_rates = np.ascontiguousarray(np.abs(rates))
    order = np.ascontiguousarray(np.argsort(-abs_rates, kind="stable"), dtype=np.int64)
    return abs_rates, abs_rates ** 4, order


def search_step(rate, t_end):
    """Event-search step (s) resolving the fastest pole ``rate`` (rad/s): ``pi/(8 rate)``."""
    return min(np.pi / (8 * rate) if rate > 0 else t_end / 1000, t_end / 20)


def grazing_error(t):
    """The ``RuntimeError`` of contact events repeating without time advancing at ``t`` (s)."""
    return RuntimeError(f"contact events repeat without time advancing at t = {t!r} s: the "
                        "contact state cannot be decided (grazing); use method='modal'")


#: a first contact spanning fewer output samples than this has its force's maximum
#: bracketed on a grid of ``_PEAK_GRID`` points of its own (t_end = 1e6 s over a 0.25 s
#: contact: one sample inside, the peak read 7 % low; 1e7 s: none, a peak of 1e-15 N)
_PEAK_GRID_BELOW, _PEAK_GRID = 16, 257


def insert_exact_peak(T, V, intervals, first_phase):
    """Insert the exact maximum of the first contact's force (a root of ``f'``) as a sample.

    The maximum is bracketed by the output samples around the largest one inside the
    contact, or, where the contact spans fewer than ``_PEAK_GRID_BELOW`` samples, on a
    grid of ``_PEAK_GRID`` points over it."""
    if not intervals or intervals[0][1] <= intervals[0][0] or first_phase is None:
        return T, V
    start, end = intervals[0]
    phase, t0, coords = first_phase
    form = phase.form
    coeffs = form.output_coefficients(phase.event_row, coords)

    def rate(x):
        return form.evaluate(coeffs, [x - t0], derivative=1)[0, 0]

    inside = np.flatnonzero((T > start) & (T < end))
    if inside.size >= _PEAK_GRID_BELOW:
        i = inside[np.argmax(V[0, inside])]
        lo, mid, hi = (T[i - 1] if i > 0 else start), T[i], (T[i + 1] if i + 1 < T.size
                                                               else end)
    else:   # a contact of few samples (a long t_end): bracket its maximum on a grid of its own
        grid = np.linspace(start, end, _PEAK_GRID)
        j = int(np.argmax(form.evaluate(coeffs, grid - t0)[0]))
        lo, mid, hi = grid[max(j - 1, 0)], grid[j], grid[min(j + 1, grid.size - 1)]
    lo, hi = max(lo, start), min(hi, end)
    for a, b in ((lo, mid), (mid, hi)):
        if b > a and rate(a) > 0 >= rate(b):
            t_peak = _root(rate, a, b)
            values = form.evaluate(form.output_coefficients(phase.rows, coords), [t_peak - t0])
            k = int(np.searchsorted(T, t_peak))
            T_out, V_out = np.empty(T.size + 1), np.empty((V.shape[0], T.size + 1))
            T_out[:k], T_out[k], T_out[k + 1:] = T[:k], t_peak, T[k:]
            V_out[:, :k], V_out[:, k], V_out[:, k + 1:] = V[:, :k], values[:, 0], V[:, k:]
            return T_out, V_out
    return T, V
