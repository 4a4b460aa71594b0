"""The two-sided (impact-damper) event loop, every contact law (phases built by
:class:`impactpred.damper._engine.Engine`).

One pass of the loop is one phase: start its closed form at the current state, find
its first event (:func:`.phase.search_event`), sample the outputs on the output
grid inside it, and apply the event (impulse, contact start, separation). Hertz
contacts are time-stepped by :mod:`.hertz`. Rigid and instantaneous contacts run
the same loop compiled (:mod:`.cycle_loop`, driven by :mod:`.cycle_compiled`) unless
``_COMPILED`` is False; this Python loop is the reference it is tested against.

Rigid (and low-restitution instantaneous) contacts: at a contact instant the damper
mass is put exactly on the stop (a rounding-level correction), a plastic Dirac impulse
zeroes the relative velocity (relative degree 2), and :func:`decide` chooses, once,
between the stuck phase and a separation from the sign of the first non-zero Taylor
coefficient of the force the stuck phase would need. The phase chosen starts with its
event row "open" (never an event at its start), so an event never repeats at the same
time: grazing returns and accumulations of micro-impacts resolve into sticking or into
separations that advance time. A stuck phase ends where its force crosses zero; the
free flight then starts open from the stop.

Instantaneous impacts with restitution ``e``: the rebound ``u = e v`` is applied unless
:func:`.cycle_loop.zeno_closes` finds it unresolved (the end of a Zeno sequence,
whose bounces under the relative acceleration ``a`` accumulate at
``t + 2 u / (a (1 - e))``; or stops that coincide to the gap's resolution, where the
impacts ``v, e v, e^2 v, ...`` at one instant sum to a plastic one); the impact is then
the Rigid law's plastic impact and decision above (the same code). The rule's scales do
not vanish with the clearance: ``clearance = 0`` with ``e < 1`` is the Rigid law at
``clearance = 0``, the damper mass moving with the primary. Both loops raise a
``RuntimeError`` after more than ``cycle_compiled.MAX_IMPACTS_PER_PERIOD`` impacts
within one forcing period, so that a run's cost per cycle is bounded.

Linear spring(-dashpot) contacts (``f = max(0, k d + c d')`` while the penetration
``d > 0``): the force law is continuous across ``q = k d + c d' = 0`` (the vector field
does not jump there), and jumps by ``c d'`` across ``d = 0`` only where ``d' != 0``. The
phases are free flight (``d < 0``), spring contact (``d > 0``, ``q > 0``) and
penetrating flight (``d > 0``, ``q <= 0``: the dashpot would pull, the force is 0). At
every boundary between them (a gap or penetration reaching 0, ``q`` reaching 0) the
state is put exactly on that boundary (:func:`run`'s ``spring_boundary``: ``d = 0``, or
``q = 0`` through a rounding-level shift of ``y_d``) and :func:`decide_row` is applied once
to the force the spring phase would have: positive, the spring phase; negative, the
free or penetrating flight. The phase chosen starts with its event row open, so the
decision cannot flip back at the same instant (two phases' closed forms round the same
``q`` differently, at levels above each other's zero tolerance).
"""

from __future__ import annotations

import math

import numpy as np

from ..contact import InstantaneousImpact, LinearSpring, Rigid
from . import cycle_compiled
from .cycle_compiled import run_compiled, runaway_error, stall_error
from .cycle_loop import STALL, ZERO_RTOL, _decide, row_sizes, zeno_closes
from .cycle_state import OUT_BV, OUT_FEQ, OUT_LAM, OUT_VP, EngineState
from .hertz import hertz_contact
from .phase import evaluate, search_event

__all__ = ["run"]

_STALL = STALL       # phases in a row without time advancing (the compiled loop's rule)
#: the event search of this loop (tests swap in the Python oracle of the compiled search)
_SEARCH = search_event
#: rigid and instantaneous contacts run in the compiled loop (:mod:`.cycle_loop`); False:
#: this module's Python loop (the reference the compiled one is tested against)
_COMPILED = True


def _integral(lam, b, poly, tau):
    """``int_0^tau Re(b e^{lam s}) + poly(s) ds`` for each row of ``b`` (scalar ``tau``)."""
    z = lam * tau
    with np.errstate(divide="ignore", invalid="ignore"):
        e = np.where(lam == 0, tau, np.expm1(z) / np.where(lam == 0, 1.0, lam))
    out = (b @ e).real
    for j in range(poly.shape[1]):
        out = out + poly[:, j] * tau ** (j + 1) / (j + 1)
    return out


def _work(a, lam, vb, taus):
    """``int_0^tau Re(a_r e^{i w s}) Re(sum vb e^{lam s}) ds`` for each ``a_r`` of ``a``.

    ``lam[-1] = i w``; returns shape (len(a), len(taus)).
    """
    iw = lam[-1]
    out = np.zeros((a.size, taus.size))
    for mu, coef in ((iw + lam, vb), (iw + lam.conj(), vb.conj())):
        zero = mu == 0.0
        mu_safe = np.where(zero, 1.0, mu)
        e = np.expm1(np.outer(mu, taus)) / mu_safe[:, None]
        e[zero] = taus
        out += 0.5 * (np.outer(a, coef) @ e).real
    return out


#: a Taylor coefficient of the stuck force is zero when below this fraction of the sum of
#: the magnitudes it is computed from (its rounding is ~1e-16 of that sum)
_DECIDE_RTOL = 1e-10


def decide(lam, b, poly, *, first=0):
    """Stick (True) or separate, at a contact instant with zero relative velocity.

    ``f(tau) = Re(sum b e^{lam tau}) + poly(tau)`` is the compressive force the stuck
    phase would need. Its first Taylor coefficient at ``tau = 0`` that is not zero to
    rounding decides: positive, stick; negative, separate. With ``f^(j)(0) = 0`` for
    ``j < k``, the free flight's gap has ``g^(j+2)(0) = 0`` for ``j < k`` and
    ``g^(k+2)(0) = -f^(k)(0) (1/m_d + 1/M_eff)`` (same for relative degrees 0 and 1 with
    their own factor), so exactly one of the two phases is consistent (Signorini's
    condition ``g >= 0, f >= 0, f g = 0`` on a right neighbourhood): stick when the free
    flight would penetrate, separate when the stuck phase would pull. Every coefficient
    zero to rounding (grazing to order 3): stick; the stuck phase's own
    search then finds where the force turns tensile, at a later time. The decision is
    taken once per contact instant, so no event can repeat at the same time.

    ``first = 1``: ``f(0) = 0`` by construction and is skipped. With a flexibility term
    (relative degree 0) the stuck force is ``-g_free / D``, zero once the damper mass is
    pinned on the stop; its closed form's rounding there (the eigenvector conditioning
    times the terms, ~1e-9 of them) must not decide.
    """
    # the compiled loop's own rule (one implementation), four Taylor orders
    return bool(_decide(np.ascontiguousarray(lam, dtype=complex),
                        np.ascontiguousarray(b, dtype=complex),
                        np.ascontiguousarray(poly, dtype=float), _DECIDE_RTOL, first))


def decide_row(row, M, xa, *, first=0, orders=4):
    """:func:`decide` from the state: the sign of ``row`` along ``xa' = M xa``.

    The Taylor coefficients ``f^(j)(0) = row M^j xa`` (``j = first .. orders - 1``) are
    computed in the state space, each with its rounding scale ``|row| |M|^j |xa|``
    (a closed form's coefficients round relative to its own terms, which may be far
    smaller than what they cancel down from). The first one above ``_DECIDE_RTOL`` of
    its scale decides: positive, True. All zero to rounding: True. ``first = 1`` when
    the value itself is zero by construction (the state was put on ``row xa = 0``).
    """
    r, ra = np.asarray(row, float), np.abs(row)
    aM, ax = np.abs(M), np.abs(xa)
    for j in range(orders):
        if j >= first:
            d, mag = float(r @ xa), float(ra @ ax)
            if abs(d) > _DECIDE_RTOL * mag:
                return d > 0.0
        r, ra = r @ M, ra @ aM
    return True


class _Progress:
    """The run's tqdm bar in cycles, "impact damper [###...] 40% (16/40 cycles)" on stderr."""

    def __init__(self, enabled, n_cycles, t_start, period):
        self.enabled, self.n, self.t0, self.T = enabled, n_cycles, t_start, period
        self.bar = None

    def update(self, t):
        if not self.enabled:
            return
        done = min(self.n, int((t - self.t0) / self.T + 1e-9))
        if self.bar is None:
            from ..parallel import progress_bar

            self.bar = progress_bar(self.n, desc="impact damper", mininterval=0.0, miniters=1,
                                    bar_format="{desc} [{bar:25}] {percentage:3.0f}% "
                                               "({n}/{total} cycles)")
        if done > self.bar.n:
            self.bar.update(done - self.bar.n)
        if done >= self.n:
            self.bar.close()
            self.enabled = False


def run(eng, *, start: EngineState, n_cycles, samples_per_cycle, progress):
    """Simulate ``n_cycles`` forcing periods from ``start``; returns a dict of raw outputs."""
    if (_COMPILED and isinstance(eng.contact, (Rigid, InstantaneousImpact))
            and start.mode in ("free", "stuck")):
        return run_compiled(eng, start=start, n_cycles=n_cycles,
                            samples_per_cycle=samples_per_cycle,
                            bar=_Progress(progress, n_cycles, start.time, eng.period),
                            decide_rtol=_DECIDE_RTOL)
    T = eng.period
    dt_out = T / samples_per_cycle
    t0_run = start.time
    t_end = t0_run + n_cycles * T
    n = eng.n
    t, x = start.time, np.array(start.state, dtype=float)
    mode, side = start.mode, start.side
    contact = eng.contact
    impacts = []
    cur = dict(start.open_impact) if start.open_impact is not None else None
    if cur is not None:
        cur["continued"] = True
        impacts.append(cur)
    chunks_t, chunks_v, chunks_w, chunks_g = [], [], [], []
    work = np.zeros(2)
    v_max = eng.c * eng.omega       # the Zeno rule's velocity scale (m/s)
    max_impacts = cycle_compiled.MAX_IMPACTS_PER_PERIOD
    on_boundary = mode != "free"
    open_row = None           # event row decided to open at the phase's start
    zero_open = False         # ... and 0 there by construction (spring contact)
    stall = crawl = 0
    bar = _Progress(progress, n_cycles, t0_run, T)
    bar.update(t)
    first_sample = True

    def emit(kind, coords, t_a, tau):
        nonlocal first_sample
        ob, op = kind.coefficients(kind.output, coords)
        j_lo = int(math.floor((t_a - t0_run) / dt_out + 1e-9)) + 1
        j_hi = int(math.ceil((t_a + tau - t0_run) / dt_out - 1e-9)) - 1
        grid = np.arange(j_lo, j_hi + 1)
        taus = t0_run + grid * dt_out - t_a
        keep = (taus > 0) & (taus < tau)
        grid, taus = grid[keep], taus[keep]
        end_j = (t_a + tau - t0_run) / dt_out
        end_grid = int(round(end_j)) if abs(end_j - round(end_j)) < 1e-7 else -1
        lead = [0.0] if first_sample else []
        lead_g = [0] if first_sample else []
        first_sample = False
        taus = np.concatenate([lead, taus, [tau]])
        grid = np.concatenate([lead_g, grid, [end_grid]])
        vals = evaluate(kind.lam, ob, op, taus)[0]
        w = _work(ob[OUT_FEQ:OUT_BV + 1, -1], kind.lam, ob[OUT_VP], taus) + work[:, None]
        chunks_t.append(t_a + taus)
        chunks_v.append(np.delete(vals, [OUT_FEQ, OUT_BV], axis=0))   # not the work weights
        chunks_w.append(w)
        chunks_g.append(grid)
        work[:] = w[:, -1]
        return ob, op

    r0A = eng.r0 @ eng.A      # relative velocity row (free flight; no Dirac part)
    r0AA = r0A @ eng.A        # relative acceleration row (free flight)

    def pin(x, t, s, velocity):
        """Put the damper mass exactly on stop ``s`` (and at zero relative velocity).

        Removes the rounding-level drift of a located contact instant or of a stuck
        phase (a constraint kept only to rounding by its closed form), which would
        otherwise accumulate over thousands of contacts.
        """
        xa = eng.augmented(x, t)
        x = x.copy()
        x[eng.iy] += s * eng.c - float(eng.r0 @ xa)
        if velocity:
            x[eng.iv] -= float(r0A @ xa)
        return x

    def sticks(s, x, t):
        """Contact decision at side ``s`` with the relative velocity zero (see ``decide``)."""
        kind = eng.stuck(s)
        coords = kind.start(x, t)
        b, poly = kind.coefficients(kind.event, coords)
        i = 0 if s == 1 else 1
        return decide(kind.lam, b[i], poly[i], first=1 if eng.rho == 0 else 0)

    def spring_boundary(s, x, t, q_zero):
        """Next phase at a boundary of the linear-spring contact at side ``s``.

        ``q_zero``: the event located ``q = k d + c d' = 0`` (else ``d = 0``). The state is
        put exactly on the boundary (a rounding-level correction: ``d = 0`` and, with
        ``q = 0`` too, ``d' = 0``; or ``q = 0`` through ``y_d`` when ``d > 0``), then
        :func:`decide_row` on the spring phase's force chooses, once. Returns
        ``(x, mode, open_row, zero_start)``; ``zero_start``: the open row is 0 at the
        start by the correction (its closed form's rounding there is removed).
        """
        k, cd = contact.stiffness, contact.damping
        xa = eng.augmented(x, t)
        rel = float(eng.r0 @ xa)
        d = s * rel - eng.c
        # a gap / penetration event located d = 0; q = 0 is on the stop too when d
        # is 0 to rounding there (then d' = 0 as well) or without a dashpot (q = k d)
        on_stop = not q_zero or cd == 0.0 or d <= 1e-12 * max(eng.c, abs(rel))
        if on_stop:
            x = pin(x, t, s, q_zero and cd > 0.0)
        else:           # d > 0 at q = 0 (cd > 0, so no flexibility term: d_p = 0)
            q = k * d + cd * s * float(r0A @ xa)
            x = x.copy()
            x[eng.iy] -= s * q / k
        kind = eng.spring(s)
        xa = eng.augmented(x, t)
        # at d = 0 the value is c d' (nonzero unless grazing); at q = 0 it is 0
        if decide_row(kind.event_row, kind.M_aug, xa, first=1 if q_zero else 0):
            f0 = float(kind.event_row @ xa)
            zero_start = q_zero or abs(f0) <= _DECIDE_RTOL * float(
                np.abs(kind.event_row) @ np.abs(xa))
            return x, "spring", 0, zero_start
        if on_stop:
            return x, "free", (0 if s == 1 else 1), True
        return x, "pen", 0, True

    def open_impact(s, t, v_rel):
        phase = (eng.omega * t + eng.phi) % (2 * math.pi)
        rec = dict(time=t, side=s, impulse=0.0, duration=0.0, relative_velocity=v_rel,
                   phase=phase, continued=False)
        impacts.append(rec)
        return rec

    while t < t_end - 1e-12 * T:
        if mode == "hertz":
            t_new, x, impulse, samples, closed = hertz_contact(eng, x, t, side, t_end, t0_run,
                                                               dt_out)
            w0 = work.copy()
            for ts, vals, g, dw in samples:
                # Hertz samples carry the input work since the contact phase's start
                chunks_t.append(ts)
                chunks_v.append(vals)
                chunks_w.append(w0[:, None] + dw)
                chunks_g.append(g)
                work[:] = w0 + dw[:, -1]
            first_sample = False
            cur["impulse"] += impulse
            cur["duration"] = t_new - cur["time"]
            stall = stall + 1 if t_new == t else 0
            t = t_new
            mode, on_boundary = ("hertz" if closed else "free"), True
            if not closed:      # left at the exit with the gap opening (0 to rounding)
                open_row = 0 if side == 1 else 1
            bar.update(t)
            continue
        if mode == "free":
            kind, sel = eng.free, slice(0, 2)
        elif mode == "stuck":
            kind = eng.stuck(side)
            sel = slice(0, 1) if side == 1 else slice(1, 2)
        elif mode == "spring":
            kind, sel = eng.spring(side), slice(0, 1)
        else:  # "pen"
            eng.spring(side)
            kind, sel = eng._pen[side], slice(0, 2)
        coords = kind.start(x, t)
        b, poly = kind.coefficients(kind.event, coords)
        b, poly = b[sel], poly[sel]
        if open_row is not None and poly.shape[1] and (mode == "free" or zero_open):
            # the damper mass was put exactly on the stop: the open gap row is 0 at the
            # start; remove the closed form's rounding there (it scales with the
            # eigenvector conditioning and may exceed the rows' zero tolerance)
            poly = poly.copy()
            poly[open_row, 0] -= float(b[open_row].real.sum() + poly[open_row, 0])
        total = row_sizes(np.ascontiguousarray(b), np.ascontiguousarray(poly), T)
        zero_tol = ZERO_RTOL * total + 1e-300
        scale = np.full(total.shape, eng.c) if (mode == "free" and eng.c > 0) else total
        tau, row = _SEARCH(kind, b, poly, t_end - t, scale=scale, zero_tol=zero_tol,
                               on_boundary=on_boundary,
                               open_rows=() if open_row is None else (open_row,))
        open_row, zero_open = None, False
        happened = tau is not None
        if not happened:
            tau = t_end - t
        ob, op = emit(kind, coords, t, tau)
        if mode in ("stuck", "spring") and cur is not None:
            cur["impulse"] += side * float(_integral(kind.lam, ob[OUT_LAM:OUT_LAM + 1],
                                                      op[OUT_LAM:OUT_LAM + 1], tau)[0])
        x = kind.state(coords, tau)
        stall = stall + 1 if tau == 0.0 else 0
        crawl = crawl + 1 if tau < 1e-9 * T else 0
        if stall > _STALL or crawl > 100 * _STALL:
            raise stall_error(eng, t, mode)
        t = t + tau
        bar.update(t)
        if not happened:
            break
        on_boundary = True
        if mode == "free":
            s = 1 if row == 0 else -1
            xa = eng.augmented(x, t)
            v_rel = -eng.gap_rate(xa, s)
            v_max = max(v_max, v_rel)
            if isinstance(contact, LinearSpring):
                x, mode, open_row, zero_open = spring_boundary(s, x, t, False)
                side = s
                if mode == "spring":        # a grazing touch without force is no impact
                    cur = open_impact(s, t, v_rel)
                continue
            cur = open_impact(s, t, v_rel)
            if len(impacts) > max_impacts and impacts[-1 - max_impacts]["time"] > t - T:
                raise runaway_error(eng, t, v_rel, max_impacts)
            if isinstance(contact, (Rigid, InstantaneousImpact)):
                x = pin(x, t, s, False)
                e = contact.restitution if isinstance(contact, InstantaneousImpact) else 0.0
                acc = -s * float(r0AA @ eng.augmented(x, t))
                if zeno_closes(e, v_rel, acc, eng.c, float(zero_tol[row]), v_max):
                    # plastic (Rigid, or the limit of a Zeno sequence): zero the relative
                    # velocity (a Dirac only where the gap has relative degree 2), then decide
                    p = max(v_rel, 0.0) / eng.inv_mu if eng.rho == 2 else 0.0
                    x = x + s * p * eng.Bl[:n]
                    cur["impulse"] += p
                    if eng.rho == 2:
                        x = pin(x, t, s, True)
                    stick = sticks(s, x, t)
                else:
                    p = (1.0 + e) * v_rel / eng.inv_mu
                    x = x + s * p * eng.Bl[:n]
                    cur["impulse"] += p
                    stick = False
                if stick:
                    # relative degree 0: the stuck force -g_free/D is 0 at the start
                    mode, side, open_row, zero_open = "stuck", s, 0, eng.rho == 0
                else:
                    mode, open_row = "free", (0 if s == 1 else 1)
            else:
                mode, side = "hertz", s
        elif mode == "stuck":
            cur["duration"] = t - cur["time"]
            x = pin(x, t, side, eng.rho == 2)
            mode, open_row = "free", (0 if side == 1 else 1)
        elif mode == "spring":
            if cur is not None:
                cur["duration"] = t - cur["time"]
            x, mode, open_row, zero_open = spring_boundary(side, x, t, True)
        else:  # pen: row 0 is -q, row 1 the penetration
            x, mode, open_row, zero_open = spring_boundary(side, x, t, row == 0)
    if cur is not None and mode in ("stuck", "spring", "hertz"):
        cur["duration"] = t - cur["time"]
    if mode == "free" or cur is None or mode == "pen":
        open_rec = None
    else:                            # the open impact so far, its duration to t included
        open_rec = {k: v for k, v in cur.items() if k != "continued"}
    bar.update(t_end)
    return dict(
        t=np.concatenate(chunks_t), values=np.concatenate(chunks_v, axis=1),
        work=np.concatenate(chunks_w, axis=1), grid=np.concatenate(chunks_g),
        impacts=impacts,
        final=EngineState(t, x, mode, side, open_rec),
        t_start=t0_run, t_end=t_end)
