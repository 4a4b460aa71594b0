"""Driver of the compiled event loop (:mod:`.cycle_loop`) for rigid and instantaneous
contacts: packs the engine's phase kinds into arrays, calls the loop on chunks of cycles
(the progress bar is updated between chunks, and the samples of one chunk are all that is
held in compiled arrays at once) and returns :func:`.cycle_run.run`'s dict.

A chunk boundary does not cut a phase: every event search looks up to the run's end and
the loop stops at the first event after the chunk's end, so the chunks give exactly the
run itself. A call also pauses after ``PHASES_PER_CALL`` phases (the bar is redrawn, then
the chunk goes on from the same state), so that a run with many contacts per cycle still
reports progress; more than ``MAX_IMPACTS_PER_PERIOD`` impacts within one forcing period
raise a ``RuntimeError`` (the cost per cycle is bounded).
"""

from __future__ import annotations

import numpy as np

from ..contact import InstantaneousImpact
from .cycle_loop import N_IMPACT_COLS, PAUSED, RUNAWAY, STALLED, rigid_loop
from .cycle_state import EngineState

__all__ = ["kind_arrays", "run_compiled", "runaway_error", "stall_error"]

#: forcing cycles per call of the compiled loop
CHUNK_CYCLES = 50
#: phases per call of the compiled loop at most (~0.1-0.5 s): the progress bar is redrawn
#: at least this often
PHASES_PER_CALL = 20_000
#: impacts allowed within any window of one forcing period (both loops): more raise a
#: ``RuntimeError``. The Zeno rule closes an accumulation of impacts after about
#: ``14 / (1 - e)`` of them (``ln(1e12) / (2 ln(1/e))``: bounce heights from the gap's
#: scale to its resolution), so a run past this cap has impacts that do not accumulate
#: (``e`` = 1 between nearly coincident stops, or a restitution within ~1e-4 of 1).
MAX_IMPACTS_PER_PERIOD = 100_000


def stall_error(eng, t, phase):
    """The ``RuntimeError`` of contact events repeating without time advancing at ``t`` (in
    the engine's unit of time, ``eng.units.t``) in a ``phase`` ("free", "stuck", ...)
    phase; its message in SI."""
    hint = ""
    u = eng.units             # the engine's dimensionless form: t, c and omega in SI here
    if isinstance(eng.contact, InstantaneousImpact) and eng.contact.restitution == 1.0:
        hint = (f"; with restitution 1 an impact between stops that coincide to rounding "
                f"(clearance {eng.c * u.l!r} m) rebounds into the other stop for ever: use a "
                f"restitution below 1 or a larger clearance")
    near = float(np.finfo(float).eps) / max(eng.resonance_error(), 1e-300)
    if near < 1e-6:     # the phases' rounding, eps / near, decides the grazing contacts
        hint += (f"; the excitation frequency {eng.omega_si / (2 * np.pi)!r} Hz lies within a "
                 f"relative {near:.2g} of an undamped mode of a phase, where the response "
                 f"is rounded to {eng.resonance_error():.2g} of itself: move the frequency "
                 f"off the mode or give it some damping")
    t_si = float(t) * u.t
    return RuntimeError(f"contact events repeat without time advancing at t = {t_si!r} s "
                        f"({phase} phase): the contact state cannot be decided (grazing)"
                        + hint)


def runaway_error(eng, t, v_rel, cap):
    """The ``RuntimeError`` of a run with more than ``cap`` impacts within one forcing period
    (before ``t``; ``v_rel``: the last approach velocity; both on the engine's dimensionless
    form, ``eng.units``); its message in SI."""
    e = eng.contact.restitution if isinstance(eng.contact, InstantaneousImpact) else 0.0
    u = eng.units             # the engine's dimensionless form: back to SI here
    t_si, v_si = float(t) * u.t, float(v_rel) * u.l / u.t
    return RuntimeError(
        f"more than {cap} impacts within one forcing period (T = {eng.period_si!r} s) before "
        f"t = {t_si!r} s (last approach velocity {v_si!r} m/s): the impacts "
        f"do not accumulate into sticking (restitution {e!r}, clearance {eng.c * u.l!r} m). "
        f"Elastic or nearly elastic impacts between (nearly) coincident stops never end; use "
        f"a lower restitution, a larger clearance or Rigid()")


def kind_arrays(kind):
    """The arrays of a :class:`.phase.PhaseKind` as :func:`rigid_loop` takes them
    (built once per kind): ``(lam, abs_lam, abs_lam4, order, V, Vinv, in0, S0P, X, ev_rv,
    ev_rp, ev_rx, out_rv, out_rp, out_rx)``."""
    arrays = getattr(kind, "_compiled_arrays", None)
    if arrays is None:
        n, k = kind.n, kind.k
        c = np.ascontiguousarray

        def rows(r):
            rv, rp, rx = r
            return (c(rv, dtype=complex), c(np.reshape(rp, (rv.shape[0], k, k)), dtype=float),
                    c(rx, dtype=complex))

        s0p = np.array(kind.S0P, dtype=float).reshape(k, n, k)
        arrays = (c(kind.lam, dtype=complex), c(kind.abs_lam, dtype=float),
                  c(kind.abs_lam4, dtype=float), c(kind.order_desc, dtype=np.int64),
                  c(kind.V, dtype=complex), c(kind.Vinv, dtype=complex),
                  c(np.reshape(kind.in0, (k, n)), dtype=float), c(s0p), c(kind.X, dtype=complex),
                  *rows(kind.event), *rows(kind.output))
        kind._compiled_arrays = arrays
    return arrays


def run_compiled(eng, *, start, n_cycles, samples_per_cycle, bar, decide_rtol):
    """:func:`.cycle_run.run` for ``Rigid`` / ``InstantaneousImpact`` contacts, compiled.

    ``bar``: the run's progress bar (``update(t)``); ``decide_rtol``: the contact
    decision's tolerance. Raises ``RuntimeError`` where contact events repeat without time
    advancing, or past ``MAX_IMPACTS_PER_PERIOD`` impacts within one forcing period (as
    the Python loop).
    """
    T = eng.period
    dt_out = T / samples_per_cycle
    t0_run = start.time
    t_end = t0_run + n_cycles * T
    t = start.time
    x = np.array(start.state, dtype=float)
    if start.mode not in ("free", "stuck"):
        raise ValueError(f"a {start.mode!r} state cannot continue with a rigid contact")
    mode, side = (0 if start.mode == "free" else 1), int(start.side)
    imp = np.zeros((max(64, 40 * n_cycles), N_IMPACT_COLS))
    n_imp, cur, continued = 0, -1, None
    if start.open_impact is not None:
        o = start.open_impact
        imp[0] = (o["time"], o["side"], o["impulse"], o["duration"], o["relative_velocity"],
                  o["phase"])
        n_imp, cur, continued = 1, 0, 0
    free = kind_arrays(eng.free)
    stuck_p, stuck_m = kind_arrays(eng.stuck(1)), kind_arrays(eng.stuck(-1))
    e = eng.contact.restitution if isinstance(eng.contact, InstantaneousImpact) else 0.0
    n = eng.n
    r0A = eng.r0 @ eng.A
    consts = (t0_run, dt_out, T, eng.iy, eng.iv, float(eng.c), eng.omega, eng.phi,
              np.ascontiguousarray(eng.r0), np.ascontiguousarray(r0A),
              np.ascontiguousarray(r0A @ eng.A), np.ascontiguousarray(eng.A),
              np.ascontiguousarray(eng.Bl[:n]), float(eng.inv_mu), int(eng.rho), float(e),
              float(decide_rtol))
    work = np.zeros(2)
    on_boundary, open_row, first_sample = mode != 0, -1, True
    stall = crawl = 0
    v_max = eng.c * eng.omega
    chunks_t, chunks_v, chunks_w, chunks_g = [], [], [], []
    done = False
    i_chunk = 0
    bar.update(t)
    status = None
    while not done:
        if status != PAUSED:
            i_chunk += 1
            t_stop = t0_run + i_chunk * CHUNK_CYCLES * T
            if t_stop <= t:         # the last call's phase ran past this chunk's end
                i_chunk = int((t - t0_run) / (CHUNK_CYCLES * T)) + 1
                t_stop = t0_run + i_chunk * CHUNK_CYCLES * T
            t_stop = min(t_stop, t_end)
        (status, t, x, mode, side, on_boundary, open_row, first_sample, stall, crawl, v_max,
         cur, imp, n_imp, ts, vs, ws, gs, done) = rigid_loop(
            free, stuck_p, stuck_m, x, t, mode, side, on_boundary, open_row, first_sample,
            stall, crawl, v_max, work, cur, imp, n_imp, t_end, t_stop, PHASES_PER_CALL,
            MAX_IMPACTS_PER_PERIOD, *consts)
        chunks_t.append(ts)
        chunks_v.append(vs)
        chunks_w.append(ws)
        chunks_g.append(gs)
        if status == STALLED:
            raise stall_error(eng, t, "free" if mode == 0 else "stuck")
        if status == RUNAWAY:
            raise runaway_error(eng, t, float(imp[n_imp - 1, 4]), MAX_IMPACTS_PER_PERIOD)
        bar.update(t)
        if status != PAUSED and t_stop >= t_end:
            done = True
    tab = imp[:n_imp]
    cont = np.zeros(n_imp, bool)
    if continued is not None:
        cont[continued] = True
    impacts = dict(time=tab[:, 0].copy(), side=tab[:, 1].astype(int), impulse=tab[:, 2].copy(),
                   duration=tab[:, 3].copy(), relative_velocity=tab[:, 4].copy(),
                   phase=tab[:, 5].copy(), continued=cont)
    mode_name = "free" if mode == 0 else "stuck"
    open_rec = None
    if mode_name == "stuck" and cur >= 0:
        impacts["duration"][cur] = t - impacts["time"][cur]
        open_rec = {k: (int(v[cur]) if k == "side" else float(v[cur]))
                    for k, v in impacts.items() if k != "continued"}
    bar.update(t_end)
    return dict(
        t=np.concatenate(chunks_t), values=np.concatenate(chunks_v, axis=1),
        work=np.concatenate(chunks_w, axis=1), grid=np.concatenate(chunks_g),
        impacts=impacts, final=EngineState(t, x, mode_name, side, open_rec),
        t_start=t0_run, t_end=t_end)
