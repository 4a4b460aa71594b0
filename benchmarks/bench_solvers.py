"""Speed and accuracy of impactpred's solvers against what a user would otherwise write.

Run:  python benchmarks/bench_solvers.py [--full] [--profile]

The case (fixed inputs)
-----------------------
A rigid mass ``M = 1 kg`` at ``v0 = 1 m/s`` strikes the free end of a fixed rod
``Rod(1.0, 1.0, support="fixed")`` (mass 1 kg, transit time ``T = 1 s``), the rod given as
its 50-mode model *with residual flexibility*, ``Rod(...).modal_model(50, residual=True)``,
over ``t_end = 8 T``. Rigid contact.

Why the residual flexibility: a truncated modal sum has ``h(0+) = 0``, so rigid contact
with it is ill posed as a force history: the exact answer has Dirac impulses (a train of
tiny plastic impacts), which a penalty spring can never reproduce, whatever its stiffness
(its answer changes with ``k_p`` and only tends to the impulsive one). With the residual
flexibility ``D`` (the dropped modes' static flexibility, a massless spring in series with
the contact) the rigid-contact problem has a bounded, Lipschitz force ``f = max(0,-g_free)/D``
and one well-defined exact solution, which a penalty model approaches as ``1/k_p -> 0``.

Even so the exact solution of this truncated model *chatters*: the one long first contact
of the continuum (0 to 3.07 s) breaks into 69 contact intervals, 8.7 ms to 0.33 s long,
separated by openings of 2.4 ms and more, plus the re-contact at 4.26 s: 70 intervals
in all, no Dirac impulse (restitution 0.696392 against the continuum's 0.698876). The benchmark measures
and prints these numbers; it does not assume them.

Methods compared
----------------
exact reference
    ``solve_impact(..., method="laplace")``: event-driven, exact to rounding. It is
    cross-checked here against the baseline with ``1/k_p = 0`` at ``rtol = 1e-10``.
baseline (what a user would write)
    ``scipy.integrate.solve_ivp(method="LSODA")`` on the first-order equations of both
    bodies, from ``ModalModel.to_statespace()`` (python-control) of each body:
    ``x_i' = A_i x_i + B_i u_i``, ``y_i = C_i x_i + D_i u_i`` with ``u_1 = -f`` (mass),
    ``u_2 = +f`` (rod). Penalty contact ``f = k_p max(0, -g)`` on the gap
    ``g = y2 - y1 = g_free + (D1 + D2) f`` with ``g_free = C2 x2 - C1 x1`` (no ``D f`` term).
    While compressed, ``f = -k_p (g_free + D f)``, so

        f = max(0, -g_free) / (1/k_p + D1 + D2)

    (the penalty spring in series with the residual flexibility). ``1/k_p = 1e-4 (D1+D2)``.
    The state is linear in each phase, so the right-hand side and its (constant) Jacobian
    are given per phase; terminal events on ``g_free`` (down-crossing in flight, up-crossing
    in contact) stop the integrator at every kink and restart it in the other phase.
    ``atol = 1e-3 rtol``; ``rtol`` is taken from a ladder (see below).
"laplace"
    Default settings (``dt`` chosen automatically: output and event-search step
    ``1/(20 omega_max)``). Exact, so at least as accurate as any baseline. Also shown: with
    ``dt = t_end`` the solver uses its own coarsest event-search step ``pi/(8 |lambda|max)``.
"modal"
    Fixed-step exact-modal (zero-order-hold) time stepping, at ``dt = T/n`` from a ladder.
"convolution"
    The exact continuum ``Rod(1, 1, support="fixed")`` with the same mass, ``dt = T/1000``,
    against the exact Saint-Venant solution (``data_synth.reference_impacts``).

Accuracy and matching
---------------------
Against the exact (laplace) solution: ``|de|``, the restitution error after all contacts;
``n``, the number of contact intervals (exact: 70); ``ep5``, the largest start/end error of
the first 5 intervals; ``ep_all``, the largest over all intervals (only when ``n`` is right).

* Baseline operating point: the loosest ``rtol`` of the ladder 1e-3 ... 1e-8 whose answer
  "matches the exact one": right ``n``, ``|de| <= 1e-3``, ``ep5 <= 1e-3 T``.
* "modal" operating point: the coarsest ``dt`` of its ladder whose accuracy is equal or
  better than the baseline operating point's in every metric (``|de|``, ``|n - n_exact|``,
  ``ep5``, and ``ep_all`` where both have the right count). If none is, the benchmark says
  so and gives the bound ``t_baseline / t_modal(finest dt tried)``: finer steps only cost
  more. A table pairs every baseline ``rtol`` with the coarsest dominating modal ``dt``.

Timing: ``time.perf_counter``, median of 5 repeats (3 for runs over 1 s), after one warm-up
run; ladder entries that are not operating points are timed once. BLAS threads are pinned
to 1 (``OPENBLAS_NUM_THREADS`` etc., unless already set): with the default threads the
small (~100 x 100) matrix products of the laplace solver slowed it 2-20x on a loaded 2-core
machine. The load average is printed: timings on a shared machine are noisy.

Options: ``--full`` extends the modal ladder to ``T/256000`` (about a minute more);
``--profile`` prints the top functions of a cProfile run of "laplace" and of "modal".
No assertions: this prints a report.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402
import scipy  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

import data_synth  # noqa: E402

try:  # data_synth is still being finished: fall back to its submodules
    from data_synth import LumpedMass, Rod  # noqa: E402
except ImportError:  # pragma: no cover
    from data_synth._base import ExactModel
    from data_synth.lumped import LumpedMass, SpringMass
    from data_synth.rod import Rod

    data_synth.ExactModel, data_synth.Rod = ExactModel, Rod
    data_synth.LumpedMass, data_synth.SpringMass = LumpedMass, SpringMass

from impactpred.api import solve_impact  # noqa: E402
from impactpred.body import Body  # noqa: E402

try:
    from data_synth.reference_impacts import mass_on_fixed_rod
except ImportError:  # pragma: no cover
    mass_on_fixed_rod = None

# ------------------------------------------------------------------------ fixed inputs
MASS = 1.0            # striker (kg)
V0 = 1.0              # approach speed (m/s)
ROD_MASS = 1.0        # kg
T = 1.0               # rod transit time (s)
N_MODES = 50
T_END = 8.0 * T
PENALTY_RATIO = 1e-4  # 1/k_p as a fraction of the series flexibility D1 + D2
K_FIRST = 5           # "first few" contact intervals for the endpoint error
TARGET = {"de": 1e-3, "ep5": 1e-3 * T}   # baseline "matches the exact answer"
RTOL_LADDER = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8)
MODAL_N = (1000, 4000, 16000, 64000)     # dt = T/n
MODAL_N_FULL = MODAL_N + (256000,)
CONV_DT = T / 1000
CONV_LIMIT = 0.2      # s
SAINT_VENANT_E = 0.6989  # restitution after all contacts (rounded), if the module is absent
GOALS = {"laplace": 100.0, "modal": 20.0}


# ---------------------------------------------------------------------------- baseline
def penalty_lsoda(models, velocities, t_end, *, rtol, atol, penalty_ratio=PENALTY_RATIO,
                  jac=True):
    """The user's baseline: LSODA on both bodies' state equations with a penalty contact.

    ``models`` are the two bodies' ``ModalModel``; body 1 approaches from below. Returns
    the restitution, the contact intervals, the number of right-hand-side evaluations and
    the number of integrator (re)starts.
    """
    blocks = []
    for model in models:
        ss = model.to_statespace()
        blocks.append((np.asarray(ss.A, float), np.asarray(ss.B, float)[:, 0],
                       np.asarray(ss.C, float)[0], float(np.asarray(ss.D)[0, 0])))
    (a1, b1, c1, d1), (a2, b2, c2, d2) = blocks
    n1, n2 = a1.shape[0], a2.shape[0]
    n = n1 + n2
    a_free = np.zeros((n, n))
    a_free[:n1, :n1], a_free[n1:, n1:] = a1, a2
    b_f = np.concatenate([-b1, b2])            # the force pushes body 1 in -y, body 2 in +y
    c_g = np.concatenate([-c1, c2])            # g_free = C2 x2 - C1 x1 (touching at t = 0)
    d_series = d1 + d2
    compliance = d_series * (1.0 + penalty_ratio)   # 1/k_p + D1 + D2
    a_contact = a_free - np.outer(b_f, c_g) / compliance   # f = -g_free / compliance

    def phase(a):
        return (lambda t, x: a @ x), (lambda t, x: a)

    free_rhs, free_jac = phase(a_free)
    contact_rhs, contact_jac = phase(a_contact)

    def gap_free(t, x):
        return c_g @ x

    gap_free.terminal = True

    x = np.zeros(n)
    for model, offset, v in ((models[0], 0, velocities[0]), (models[1], n1, velocities[1])):
        if model.inverse_mass:
            width = n1 if offset == 0 else n2
            x[offset + width - 1] = v          # rigid-body velocity: last state of the block
    t = 0.0
    in_contact = velocities[0] > velocities[1]   # touching at t = 0 and approaching
    intervals, start, nfev, starts = [], 0.0, 0, 0
    while t < t_end:
        gap_free.direction = 1.0 if in_contact else -1.0
        rhs, jacobian = (contact_rhs, contact_jac) if in_contact else (free_rhs, free_jac)
        options = {"jac": jacobian} if jac else {}
        sol = solve_ivp(rhs, (t, t_end), x, method="LSODA", rtol=rtol, atol=atol,
                        events=gap_free, **options)
        nfev += sol.nfev
        starts += 1
        if sol.status == 1 and sol.t_events[0].size:
            t, x = float(sol.t_events[0][0]), sol.y_events[0][0]
            if in_contact:
                intervals.append((start, t))
            else:
                start = t
            in_contact = not in_contact
        else:
            t, x = t_end, sol.y[:, -1]
    if in_contact:
        intervals.append((start, t_end))
    u1 = x[n1 - 1] if models[0].inverse_mass else 0.0
    u2 = x[n - 1] if models[1].inverse_mass else 0.0
    e = (u2 - u1) / (velocities[0] - velocities[1])
    return {"restitution": float(e), "intervals": tuple(intervals), "nfev": nfev,
            "starts": starts}


# --------------------------------------------------------------------------- utilities
def timed(fn, repeats):
    """(median seconds, last result) over ``repeats`` calls after one warm-up call."""
    result = fn()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), result


def timed_once(fn):
    t0 = time.perf_counter()
    result = fn()
    return time.perf_counter() - t0, result


def repeats_for(seconds):
    return 5 if seconds < 1.0 else 3


def accuracy(restitution, intervals, ref_restitution, ref_intervals):
    """Errors of a solution against the exact one (see the module docstring)."""
    iv = np.asarray(intervals, float).reshape(-1, 2)
    ref = np.asarray(ref_intervals, float).reshape(-1, 2)
    k = min(K_FIRST, len(iv), len(ref))
    ep5 = float(np.max(np.abs(iv[:k] - ref[:k]))) if k else float("inf")
    ep_all = float(np.max(np.abs(iv - ref))) if len(iv) == len(ref) else float("nan")
    return {"de": abs(restitution - ref_restitution), "n": len(iv),
            "dn": abs(len(iv) - len(ref)), "ep5": ep5, "ep_all": ep_all}


def meets_target(acc):
    return acc["dn"] == 0 and acc["de"] <= TARGET["de"] and acc["ep5"] <= TARGET["ep5"]


def at_least_as_accurate(a, b):
    """True when ``a`` is as accurate as ``b`` or better in every metric."""
    ok = a["de"] <= b["de"] and a["dn"] <= b["dn"] and a["ep5"] <= b["ep5"]
    if a["dn"] == 0 and b["dn"] == 0:
        ok = ok and a["ep_all"] <= b["ep_all"]
    return ok


def fmt_acc(acc, n_exact):
    ep_all = "-" if np.isnan(acc["ep_all"]) else f"{acc['ep_all']:.1e}"
    mark = "" if acc["n"] == n_exact else "*"
    return f"{acc['de']:9.1e} {acc['n']:4d}{mark:1s} {acc['ep5']:9.1e} {ep_all:>9s}"


def solve_quiet(*args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)   # modal: "dt is coarse"
        return solve_impact(*args, **kwargs)


def profile(label, fn, top=8):
    import cProfile
    import pstats

    prof = cProfile.Profile()
    prof.enable()
    fn()
    prof.disable()
    print(f"\n--- cProfile: {label} (top {top} by own time) ---")
    stats = pstats.Stats(prof)
    stats.sort_stats("tottime").print_stats(top)


# -------------------------------------------------------------------------------- main
def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--full", action="store_true",
                        help="extend the modal ladder to dt = T/256000")
    parser.add_argument("--profile", action="store_true",
                        help="print cProfile top functions of laplace and modal")
    args = parser.parse_args(argv)

    rod_model = Rod(ROD_MASS, T, support="fixed").modal_model(N_MODES, residual=True)
    mass_model = LumpedMass(MASS).modal_model(0)
    striker = Body(LumpedMass(MASS), velocity=V0)
    rod_body = Body(rod_model)
    continuum = Body(Rod(ROD_MASS, T, support="fixed"))

    print(f"bench_solvers: mass {MASS} kg at {V0} m/s on Rod({ROD_MASS}, {T}, fixed), "
          f"{N_MODES} modes + residual flexibility D = {rod_model.flexibility:.6g} m/N, "
          f"t_end = {T_END} s")
    print(f"python {sys.version.split()[0]}, numpy {np.__version__}, scipy {scipy.__version__}, "
          f"BLAS threads {os.environ.get('OPENBLAS_NUM_THREADS')}, cpus {os.cpu_count()}, "
          f"load average {os.getloadavg()[0]:.2f}")

    # ---- exact reference: laplace
    t_lap, exact = timed(lambda: solve_impact(striker, rod_body, t_end=T_END,
                                              method="laplace"), 5)
    e_ex, iv_ex = exact.restitution, exact.contact_intervals
    n_ex = len(iv_ex)
    iv_arr = np.asarray(iv_ex)
    lengths = iv_arr[:, 1] - iv_arr[:, 0]
    openings = iv_arr[1:, 0] - iv_arr[:-1, 1]
    print(f"\nexact 50-mode solution (laplace, output/event step {exact.dt:.3g} s): "
          f"restitution {e_ex:.9f}, {n_ex} contact intervals, lengths "
          f"{lengths.min():.3g}..{lengths.max():.3g} s, openings {openings.min():.3g}.."
          f"{openings.max():.3g} s, last contact ends at {iv_arr[-1, 1]:.4f} s, "
          f"{len(exact.dirac_impulses)} Dirac impulses")
    print("  first intervals: " + ", ".join(f"({a:.5f}, {b:.5f})" for a, b in iv_ex[:K_FIRST]))

    t_lap_coarse, coarse = timed(lambda: solve_impact(striker, rod_body, t_end=T_END,
                                                      method="laplace", dt=T_END), 5)
    acc_lap_coarse = accuracy(coarse.restitution, coarse.contact_intervals, e_ex, iv_ex)

    models, velocities = (mass_model, rod_model), (V0, 0.0)
    check = penalty_lsoda(models, velocities, T_END, rtol=1e-10, atol=1e-13, penalty_ratio=0.0)
    acc_check = accuracy(check["restitution"], check["intervals"], e_ex, iv_ex)
    print(f"  cross-check, LSODA with 1/k_p = 0 at rtol 1e-10: |de| {acc_check['de']:.1e}, "
          f"n {acc_check['n']}, max endpoint error {acc_check['ep_all']:.1e} s")

    header = f"{'|de|':>9s} {'n':>5s} {'ep5 (s)':>9s} {'ep_all(s)':>9s}"

    # ---- baseline ladder
    print(f"\nbaseline ladder: LSODA + penalty (1/k_p = {PENALTY_RATIO:g} D), atol = 1e-3 rtol"
          f"   (* = wrong interval count)")
    print(f"  {'rtol':>7s} {'time (s)':>9s} {'nfev':>7s} {'starts':>6s} {header}  target")
    ladder = []
    for rtol in RTOL_LADDER:
        el, res = timed_once(lambda: penalty_lsoda(models, velocities, T_END, rtol=rtol,
                                                   atol=1e-3 * rtol))
        acc = accuracy(res["restitution"], res["intervals"], e_ex, iv_ex)
        ladder.append((rtol, el, res, acc))
        print(f"  {rtol:7.0e} {el:9.3f} {res['nfev']:7d} {res['starts']:6d} "
              f"{fmt_acc(acc, n_ex)}  {'yes' if meets_target(acc) else 'no'}")
    floor = penalty_lsoda(models, velocities, T_END, rtol=1e-11, atol=1e-14)
    acc_floor = accuracy(floor["restitution"], floor["intervals"], e_ex, iv_ex)
    print(f"  penalty model error (rtol 1e-11): {fmt_acc(acc_floor, n_ex)}")
    passing = [entry for entry in ladder if meets_target(entry[3])]
    base_rtol, _, _, base_acc = passing[0] if passing else ladder[-1]
    t_base, _ = timed(lambda: penalty_lsoda(models, velocities, T_END, rtol=base_rtol,
                                            atol=1e-3 * base_rtol), 5)
    t_base_nojac, _ = timed(lambda: penalty_lsoda(models, velocities, T_END, rtol=base_rtol,
                                                  atol=1e-3 * base_rtol, jac=False), 3)
    print(f"  operating point: rtol {base_rtol:g} (loosest meeting |de| <= {TARGET['de']:g}, "
          f"ep5 <= {TARGET['ep5']:g} s, right count); median {t_base:.3f} s "
          f"(without the analytic Jacobian: {t_base_nojac:.3f} s)")

    # ---- modal ladder
    print(f"\nmodal ladder: dt = T/n   (* = wrong interval count)")
    print(f"  {'n':>7s} {'time (s)':>9s} {header}  >= baseline?")
    modal = []
    for n in (MODAL_N_FULL if args.full else MODAL_N):
        el, res = timed_once(lambda: solve_quiet(striker, rod_body, t_end=T_END,
                                                 method="modal", dt=T / n))
        acc = accuracy(res.restitution, res.contact_intervals, e_ex, iv_ex)
        modal.append((n, el, acc))
        print(f"  {n:7d} {el:9.3f} {fmt_acc(acc, n_ex)}  "
              f"{'yes' if at_least_as_accurate(acc, base_acc) else 'no'}")
    good = [entry for entry in modal if at_least_as_accurate(entry[2], base_acc)]
    if good:
        n_mod = good[0][0]
        t_mod, res = timed(lambda: solve_quiet(striker, rod_body, t_end=T_END,
                                               method="modal", dt=T / n_mod),
                           repeats_for(good[0][1]))
        acc_mod = accuracy(res.restitution, res.contact_intervals, e_ex, iv_ex)
        modal_ratio, modal_note = t_base / t_mod, ""
    else:
        n_mod, t_mod, acc_mod = modal[-1][0], modal[-1][1], modal[-1][2]
        modal_ratio = t_base / t_mod
        modal_note = (f"NOT REACHED: no dt down to T/{n_mod} is as accurate as the baseline; "
                      f"ratio is an upper bound")

    print("\n  pairing: each baseline rtol -> coarsest modal dt at least as accurate")
    for rtol, el, _, acc in ladder:
        match = [entry for entry in modal if at_least_as_accurate(entry[2], acc)]
        text = (f"T/{match[0][0]} ({match[0][1]:.2f} s once, ratio {el / match[0][1]:.2g})"
                if match else "none in the ladder")
        print(f"  rtol {rtol:7.0e} ({el:.2f} s once): {text}")

    # ---- convolution on the exact continuum
    t_conv, conv = timed(lambda: solve_impact(striker, continuum, t_end=T_END,
                                              method="convolution", dt=CONV_DT), 5)
    if mass_on_fixed_rod is not None:
        sv = mass_on_fixed_rod(MASS, ROD_MASS, T, V0, np.array([0.0]))
        e_sv, iv_sv = sv.restitution, sv.contact_intervals
    else:  # pragma: no cover
        e_sv, iv_sv = SAINT_VENANT_E, ()
    acc_conv = accuracy(conv.restitution, conv.contact_intervals, e_sv, iv_sv) if iv_sv else {
        "de": abs(conv.restitution - e_sv), "n": conv.n_contacts, "dn": 0,
        "ep5": float("nan"), "ep_all": float("nan")}

    # ---- summary
    print("\n" + "=" * 100)
    print(f"{'method':<44s} {'time (s)':>9s} {header}")
    print("-" * 100)
    rows = [
        (f"baseline LSODA+penalty, rtol {base_rtol:g}", t_base, base_acc),
        ("laplace (exact, default dt)", t_lap, accuracy(e_ex, iv_ex, e_ex, iv_ex)),
        (f"laplace, dt = t_end (event step {coarse.dt:.3g} s)", t_lap_coarse, acc_lap_coarse),
        (f"modal, dt = T/{n_mod}", t_mod, acc_mod),
    ]
    for name, el, acc in rows:
        print(f"{name:<44s} {el:9.4f} {fmt_acc(acc, n_ex)}")
    ref_name = "Saint-Venant" if mass_on_fixed_rod is not None else "0.6989"
    print(f"{'convolution, continuum rod, dt = T/1000':<44s} {t_conv:9.4f} "
          f"{fmt_acc(acc_conv, len(iv_sv) or acc_conv['n'])}   (vs {ref_name}: "
          f"e = {e_sv:.6f}, {len(iv_sv)} contacts)")
    print("-" * 100)
    lap_ratio = t_base / t_lap
    print(f"baseline/laplace = {lap_ratio:8.2f}x   (goal >= {GOALS['laplace']:g}x: "
          f"{'met' if lap_ratio >= GOALS['laplace'] else 'NOT met'}; with dt = t_end: "
          f"{t_base / t_lap_coarse:.2f}x)")
    print(f"baseline/modal   = {modal_ratio:8.3f}x   (goal >= {GOALS['modal']:g}x: "
          f"{'met' if good and modal_ratio >= GOALS['modal'] else 'NOT met'}) {modal_note}")
    print(f"convolution      = {t_conv:8.4f} s  (goal < {CONV_LIMIT} s: "
          f"{'met' if t_conv < CONV_LIMIT else 'NOT met'})")
    print(f"load average at the end: {os.getloadavg()[0]:.2f}")

    if args.profile:
        profile("laplace, default dt",
                lambda: solve_impact(striker, rod_body, t_end=T_END, method="laplace"))
        profile("modal, dt = T/16000",
                lambda: solve_quiet(striker, rod_body, t_end=T_END, method="modal",
                                    dt=T / 16000))


if __name__ == "__main__":
    main()
