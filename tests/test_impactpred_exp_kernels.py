"""The compiled exponential-sum kernels against closed forms and matrix exponentials, and
the certified event search as the one-clearance loop calls it (one row)."""

import math

import numpy as np
import pytest
import scipy.linalg
from scipy.optimize import brentq

from data_synth import LumpedMass, Rod
from impactpred import Body, LinearSpring, Rigid, solve_impact
from impactpred.engine import impact_run
from impactpred.engine.contact_loop import phase_run
from impactpred.engine.exp_kernels import row_value, sample_rows
from impactpred.engine.search import first_event
from impactpred.engine.spectral import SpectralPhase


def first_crossing(lam, b, poly, tau_max, zero_tol, on_boundary):
    """:func:`first_event` on one row: ``tau`` where it falls below ``-zero_tol``, or -1."""
    lam = np.asarray(lam, complex)
    if lam.size == 0:       # a polynomial alone: one null term sets the search's step
        lam, b = np.array([-8.0 / tau_max + 0j]), np.zeros(1, complex)
    abs_lam = np.abs(lam)
    order = np.argsort(-abs_lam, kind="stable").astype(np.int64)
    b, poly = np.asarray(b, complex)[None, :], np.asarray(poly, float)[None, :]
    total = np.abs(b).sum() + np.abs(poly).sum()
    tau, _ = first_event(lam, abs_lam, abs_lam**4, order, b, poly, tau_max,
                         np.array([total]), np.array([zero_tol]), on_boundary, -1)
    return tau


def _direct(lam, B, P, taus):
    e = np.exp(np.outer(lam, taus))
    return (B @ e).real + P @ (taus[None, :] ** np.arange(P.shape[1])[:, None])


def test_sample_rows_matches_direct_evaluation_on_long_grids():
    rng = np.random.default_rng(0)
    m = 40
    lam = -rng.uniform(0.0, 0.5, m) + 1j * rng.uniform(0.0, 300.0, m)
    B = rng.normal(size=(3, m)) + 1j * rng.normal(size=(3, m))
    P = rng.normal(size=(3, 3))
    h = 1e-3
    # off the grid at both ends (a phase's start, and a last step shorter than h)
    taus = np.concatenate([[0.0], 0.0007 + h * np.arange(1, 5000), [5.0002]])
    got = sample_rows(lam, B, P, taus, h)
    want = _direct(lam, B, P, taus)
    scale = np.abs(B).sum(axis=1)[:, None] + np.abs(P).sum(axis=1)[:, None] * 5.0002**2
    assert np.max(np.abs(got - want) / scale) < 1e-13


def test_first_crossing_finds_the_root_to_rounding():
    # cos(w tau) - 0.5: first root pi / (3 w)
    w = 7.0
    lam, b, poly = np.array([1j * w]), np.array([1.0 + 0j]), np.array([-0.5])
    tau = first_crossing(lam, b, poly, 10.0, 1e-12, False)
    assert tau == pytest.approx(math.pi / (3 * w), rel=4e-16)


def test_first_crossing_sees_a_dip_between_samples():
    # cos(w tau + phi) + 0.999 is negative only on |w tau + phi - pi| < 0.0447; no sample
    # of the search's grid (step pi/(8 w)) lands there
    w, phi = 1.0, 0.2
    lam, b, poly = np.array([1j * w]), np.array([np.exp(1j * phi)]), np.array([0.999])
    step = math.pi / 8 / w
    assert not np.any(np.abs(w * step * np.arange(30) + phi - math.pi) < 0.0448)
    tau = first_crossing(lam, b, poly, 10.0, 1e-12, False)
    assert tau == pytest.approx((math.acos(-0.999) - phi) / w, rel=1e-14)
    # and the tolerance only detects: the same dip not reaching -0.01 is no event
    tau = first_crossing(lam, b, poly, 10.0, 0.01, False)
    assert tau == -1.0


def test_first_crossing_looks_for_a_short_lobe_at_the_start():
    # a row starting at 0 that opens a lobe much shorter than the step, then falls:
    # tau - 100 tau^2 (root 0.01), searched with step 1
    lam, b = np.zeros(0, complex), np.zeros(0, complex)
    poly = np.array([0.0, 1.0, -100.0])
    tau = first_crossing(lam, b, poly, 5.0, 1e-12, True)
    assert tau == pytest.approx(0.01, rel=1e-14)
    # a row at rounding level that does not open: the event is at once
    poly = np.array([-1e-20, -1.0])
    assert first_crossing(lam, b, poly, 5.0, 1e-12, True) == 0.0


def test_first_crossing_reports_no_event_before_the_end():
    lam, b, poly = np.array([-1.0 + 3j]), np.array([0.2 + 0j]), np.array([1.0])
    assert first_crossing(lam, b, poly, 5.0, 1e-12, False) == -1.0


def _stiff_rows(lam, b, poly):
    """Arguments of the compiled search and of its oracle for one row."""
    from types import SimpleNamespace

    lam = np.asarray(lam, complex)
    abs_lam = np.abs(lam)
    order = np.argsort(-abs_lam, kind="stable").astype(np.int64)
    b, poly = np.asarray(b, complex)[None, :], np.asarray(poly, float)[None, :]
    kind = SimpleNamespace(lam=lam, abs_lam=abs_lam, abs_lam4=abs_lam**4, order_desc=order,
                           cuts={})
    scale = np.array([np.abs(b).sum() + np.abs(poly).sum()])
    return kind, b, poly, scale


def test_a_stiff_decaying_transient_is_searched_apart_exactly():
    """``e^{-7e6 tau} + 0.5 cos(w tau) - 0.3``: the real term (a stuck phase's stiff
    eigenvalue) is negligible after microseconds; the search ends its span there and
    restarts the rows exactly, so that the slow term sets the step from then on. The
    event is the slow term's root ``acos(0.6)/w`` (the real term then ``e^{-1e4}``):
    found to rounding, as the search of one span finds it, as the oracle does, and over
    a 1000 times longer phase, whose single-span search would take 1.4e8 steps."""
    import oracle_event_search as oracle

    from impactpred.engine.search import _search_span, _transient_end

    w = 2 * np.pi * 100.0
    kind, b, poly, scale = _stiff_rows([-7e6, 1j * w, -1j * w], [1.0, 0.25, 0.25], [-0.3])
    args = (kind.lam, kind.abs_lam, kind.abs_lam4, kind.order_desc, b, poly)
    zero_tol = np.array([1e-12])
    cut = _transient_end(kind.lam, kind.order_desc, b, poly, 5e-3, scale, zero_tol)
    assert cut == pytest.approx(math.log(1.0 / 1e-12) / 7e6, rel=1e-12)  # under zero_tol
    exact = math.acos(0.6) / w
    split = first_event(*args, 5e-3, scale, zero_tol, False, -1)
    whole = _search_span(*args, 5e-3, scale, zero_tol, False, -1)
    assert split[1] == whole[1] == 0
    assert split[0] == pytest.approx(exact, rel=1e-14)
    assert whole[0] == pytest.approx(exact, rel=1e-14)
    assert first_event(*args, 8.0, scale, zero_tol, False, -1)[0] == pytest.approx(
        exact, rel=1e-14)
    tau, row = oracle.first_event(kind, b, poly, 5e-3, scale=scale, zero_tol=zero_tol,
                                  on_boundary=False)
    assert row == 0 and tau == pytest.approx(exact, rel=1e-14)


def test_an_event_inside_the_transient_is_found_before_its_end():
    """A fast decaying oscillation (``-1e6 + 1e7 i`` rad/s) dips the row below zero within
    its first period, before the transient's end: the first span finds it, as the search
    of one span and the oracle do; a transient after which the row is near zero is not
    split off (the next span could not start clear of an event)."""
    import oracle_event_search as oracle

    from impactpred.engine.search import _search_span, _transient_end

    lam = np.array([-1e6 + 1e7j, -1e6 - 1e7j, 300j, -300j])
    kind, b, poly, scale = _stiff_rows(lam, [0.5, 0.5, 0.05, 0.05], [0.6])
    args = (kind.lam, kind.abs_lam, kind.abs_lam4, kind.order_desc, b, poly)
    zero_tol = np.array([1e-12])
    assert _transient_end(kind.lam, kind.order_desc, b, poly, 1.0, scale, zero_tol) > 0
    split = first_event(*args, 1.0, scale, zero_tol, False, -1)
    whole = _search_span(*args, 1.0, scale, zero_tol, False, -1)
    tau, row = oracle.first_event(kind, b, poly, 1.0, scale=scale, zero_tol=zero_tol,
                                  on_boundary=False)
    assert 0 < split[0] < math.pi / 1e7 and split[1] == whole[1] == row == 0
    assert split[0] == pytest.approx(whole[0], rel=1e-14)
    assert tau == pytest.approx(whole[0], rel=1e-13)
    # e^{-1e6 tau} ends at zero_tol: the row (+ 0.01) is then 0.03, within twice a
    # zero_tol of 0.02; with + 0.05 it is clear
    for const, split_off in ((0.01, False), (0.05, True)):
        k0, b0, p0, s0 = _stiff_rows([-1e6], [1.0], [const])
        cut = _transient_end(k0.lam, k0.order_desc, b0, p0, 1.0, s0, np.array([0.02]))
        assert (cut > 0.0) == split_off
        assert cut == (pytest.approx(math.log(1.0 / 0.02) / 1e6, rel=1e-12) if split_off
                       else 0.0)


def test_quiet_tail_of_a_long_span_is_certified_not_searched():
    """A body receding at 0.3 m/s from a damped vibration (``2e-3 e^{(-1 + 100 i) tau}``,
    its velocity under 0.2 m/s: the gap only grows):
    :func:`quiet_from` ends the search where the gap's growth outweighs the vibration's
    decaying bound, and the row stays positive after it (sampled densely to 5 s); a
    polynomial that dips (``(tau - 20)^2 - 4``, negative on 18-22 s) keeps its span
    to the dip; no polynomial, one of degree 4 or a growing term: the whole span. The
    searches of a 1e6 s span (the compiled one and its oracle) agree with the 50 s one,
    and the oracle's own ``quiet_from`` with the compiled one."""
    import oracle_event_search as oracle

    from impactpred.engine.step_kernels import quiet_from

    lam = np.array([-1.0 + 100j])
    b = np.array([[2e-3 + 0j]])
    zero_tol = np.array([1e-12])
    h0 = math.pi / 800
    recede = np.array([[-2e-3, 0.3, 0.0, 0.0]])     # the gap, 0 at the start
    end = quiet_from(lam, b, recede, 0.0, 1e6, h0, zero_tol)
    assert 0.0 < end < 0.1
    taus = np.linspace(end, 5.0, 200_001)
    assert _direct(lam, b, recede, taus).min() > 0.0
    dip = np.array([[396.0, -40.0, 1.0, 0.0]])                 # (tau - 20)^2 - 4
    assert 22.0 <= quiet_from(lam, b, dip, 0.0, 1e6, h0, zero_tol) < 1e6
    assert quiet_from(lam, b, np.zeros((1, 0)), 0.0, 1e6, h0, zero_tol) == 1e6
    quartic = np.array([[1.0, 0.3, 0.0, 0.0, 1e-3]])
    assert quiet_from(lam, b, quartic, 0.0, 1e6, h0, zero_tol) == 1e6
    # a longer block whose top coefficients are 0 is the cubic it is (two rigid bodies)
    padded = np.concatenate([recede, np.zeros((1, 2))], axis=1)
    assert quiet_from(lam, b, padded, 0.0, 1e6, h0, zero_tol) == end
    # a growing term (a model given with check_passive=False): no decaying bound, the
    # whole span searched; 2 + e^{1e-6 tau} cos(tau) first falls below 0 near 6.93e5 s
    grow = np.array([1e-6 + 1j])
    assert quiet_from(grow, np.array([[1.0 + 0j]]), np.array([[2.0, 0.0]]), 0.0, 8e5, 0.4,
                      zero_tol) == 8e5
    kind, b1, p1, scale = _stiff_rows(grow, [1.0], [2.0])
    tau, _ = first_event(kind.lam, kind.abs_lam, kind.abs_lam4, kind.order_desc, b1, p1,
                         8e5, scale, zero_tol, False, -1)
    assert math.exp(1e-6 * tau) * math.cos(tau) == pytest.approx(-2.0, abs=1e-9)
    assert 6.9e5 < tau < 6.95e5
    # the oracle's own quiet_from agrees on random receding and dipping rows
    rng = np.random.default_rng(5)
    for _ in range(200):
        lam_r = -rng.uniform(0.0, 2.0, 3) + 1j * rng.uniform(0.0, 200.0, 3)
        b_r = (rng.normal(size=(2, 3)) + 1j * rng.normal(size=(2, 3))) * 1e-3
        p_r = np.column_stack([rng.uniform(-1e-2, 1e-2, 2), rng.uniform(0.0, 0.5, 2),
                               rng.uniform(-1e-3, 1e-3, 2), rng.uniform(0, 1e-6, 2)])
        args = (lam_r, b_r, p_r, 0.0, 1e4, 0.01, np.full(2, 1e-12))
        assert quiet_from(*args) == pytest.approx(oracle.quiet_from(*args), rel=1e-12)
    # the whole search: no event after the start on the receding row, the dip's root found
    kind, b1, p_dip, scale = _stiff_rows(lam, b[0], dip[0])
    args = (kind.lam, kind.abs_lam, kind.abs_lam4, kind.order_desc, b1)
    root = first_event(*args, p_dip, 50.0, scale, zero_tol, False, -1)[0]
    assert root == pytest.approx(18.0, rel=1e-10)      # the vibration: 3e-11 at 18 s
    assert first_event(*args, p_dip, 1e6, scale, zero_tol, False, -1)[0] == root
    tau, row = oracle.first_event(kind, b1, p_dip, 1e6, scale=scale, zero_tol=zero_tol,
                                  on_boundary=False)
    assert row == 0 and tau == pytest.approx(root, rel=1e-13)
    kind, b1, p_rec, scale = _stiff_rows(lam, b[0], recede[0])
    assert first_event(*args, p_rec, 1e6, scale, zero_tol, True, 0) == (-1.0, -1)
    assert oracle.first_event(kind, b1, p_rec, 1e6, scale=scale, zero_tol=zero_tol,
                              on_boundary=True, open_rows=(0,)) == (None, -1)


def test_a_long_run_after_the_last_contact_changes_nothing():
    """A mass struck back from a damped spring-mass: the same contact, restitution and
    final gap growth whether the run ends at 2 s or at 1e6 s (whose free flight the
    search now certifies in steps doubling over its span)."""
    from data_synth import SpringMass

    runs = [solve_impact(Body(LumpedMass(0.5), velocity=1.0),
                         Body(SpringMass(1.0, 1e4, damping_ratio=0.01)), t_end=t_end,
                         dt=t_end / 100) for t_end in (2.0, 1e6)]
    assert [r.n_contacts for r in runs] == [1, 1]
    assert runs[1].restitution == pytest.approx(runs[0].restitution, rel=1e-12)
    np.testing.assert_allclose(runs[1].contact_intervals, runs[0].contact_intervals, rtol=1e-12)
    v_rel = (runs[1].gap[-1] - runs[1].gap[-2]) / (runs[1].t[-1] - runs[1].t[-2])
    assert v_rel == pytest.approx(runs[0].restitution * 1.0, rel=1e-6)


def test_rows_restarted_later_are_the_same_rows():
    """``_shifted`` (compiled) and the oracle's: ``b e^{lam t}`` and the cubic's Taylor
    coefficients at ``t``, the same values at every later time."""
    import oracle_event_search as oracle

    from impactpred.engine.search import _shifted

    rng = np.random.default_rng(3)
    lam = -rng.uniform(0, 50, 6) + 1j * rng.uniform(0, 500, 6)
    b = rng.normal(size=(2, 6)) + 1j * rng.normal(size=(2, 6))
    poly = rng.normal(size=(2, 4))
    t, taus = 0.0123, np.linspace(0.0, 0.05, 7)
    want = _direct(lam, b, poly, t + taus)
    for b_t, p_t in (_shifted(lam, b, poly, t), oracle._shifted(lam, b, poly, t)):
        np.testing.assert_allclose(_direct(lam, b_t, p_t, taus), want, rtol=0, atol=1e-13)


def test_row_value_derivatives_match_finite_differences():
    rng = np.random.default_rng(1)
    lam = -rng.uniform(0, 1, 5) + 1j * rng.uniform(0, 10, 5)
    b = rng.normal(size=5) + 1j * rng.normal(size=5)
    poly = rng.normal(size=4)
    h = 1e-5
    for d in (0, 1):
        fd = (row_value(lam, b, poly, 0.3 + h, d) - row_value(lam, b, poly, 0.3 - h, d)) / (2 * h)
        assert fd == pytest.approx(row_value(lam, b, poly, 0.3, d + 1), rel=1e-7)


def test_phase_run_matches_the_matrix_exponential():
    # a rigid mass (nilpotent block) and two damped modes, coupled
    rng = np.random.default_rng(2)
    M = np.zeros((6, 6))
    M[0, 1] = 1.0
    M[2:4, 2:4] = [[0.0, 1.0], [-400.0, -0.4]]
    M[4:6, 4:6] = [[0.0, 1.0], [-2500.0, -1.0]]
    M[1, 2] = 30.0
    M[3, 0] = 5.0
    sp = SpectralPhase(M)
    rows = rng.normal(size=(3, 6))
    event_row = np.array([1.0, 0.0, 0.0, 0.0, 0.0, 0.0]) + 0.0  # the mass's displacement
    x = rng.normal(size=6)
    x[0] = 2.0
    (po, eo), (pe, ee) = sp.project(rows), sp.project(event_row)
    e0 = float(event_row @ x)
    abs_r = np.abs(sp.rates)
    order = np.argsort(-abs_r, kind="stable").astype(np.int64)
    tau, x_end, times, values = phase_run(sp.rates, abs_r, abs_r**4, order,
                                          sp._modes.real.copy(), sp._modes.imag.copy(),
                                          sp._proj.real.copy(), sp._proj.imag.copy(), sp.in0,
                                          sp._s0_powers, po, eo, pe, ee,
                                          np.abs(event_row) @ np.abs(sp._modes), x, 0.3, 2.3,
                                          0.01, 1e-12, True, False)
    t_stop = tau if tau >= 0 else 2.0
    assert x_end == pytest.approx(scipy.linalg.expm(M * t_stop) @ x, rel=1e-11, abs=1e-11)
    assert times[0] == 0.3 and times[-1] == pytest.approx(0.3 + t_stop, rel=1e-15)
    assert np.all(np.diff(times[1:-1]) == pytest.approx(0.01))
    want = np.array([rows @ (scipy.linalg.expm(M * (t - 0.3)) @ x) for t in times]).T
    assert np.max(np.abs(values - want)) < 1e-10 * np.max(np.abs(want))
    if tau >= 0:
        assert event_row @ x_end == pytest.approx(0.0, abs=1e-12 * abs(e0))


@pytest.mark.parametrize("h", [1e-8, 2e-7, 1e-5, 0.05, 2.0])     # Taylor series to 1.3e-6
def test_product_integrals_are_exact_beside_a_stiff_pole(h):
    """``int_0^h (a x)(b x) dt`` of a rigid mass (nilpotent block, polynomial terms), two
    damped modes and a stiff real pole (-3e6 rad/s: a contact of 2 s is 6e6 of its time
    constants, which a quadrature on its scale could not afford): the spectral closed form
    and Van Loan's block exponential (the matrix-exponential fallback) against a
    quadrature of the matrix exponential's solution, split where the stiff pole decays."""
    from scipy.integrate import quad

    M = np.zeros((7, 7))
    M[0, 1] = 1.0
    M[2:4, 2:4] = [[0.0, 1.0], [-400.0, -0.4]]
    M[4:6, 4:6] = [[0.0, 1.0], [-2500.0, -1.0]]
    M[6, 6] = -3e6
    M[1, 2], M[1, 6], M[3, 6] = 30.0, 2e3, 50.0      # the modes and the stiff term drive the mass
    rng = np.random.default_rng(4)
    rows, x0 = rng.normal(size=(3, 7)), rng.normal(size=7)
    pairs = ((0, 1), (0, 2), (1, 1))

    def integrand(t, a, b):
        x = scipy.linalg.expm(M * t) @ x0
        return (rows[a] @ x) * (rows[b] @ x)

    cut = min(h, 40.0 / 3e6)
    want = np.array([sum(quad(integrand, lo, hi, args=(a, b), epsabs=0.0, epsrel=1e-12,
                              limit=400)[0] for lo, hi in ((0.0, cut), (cut, h)) if hi > lo)
                     for a, b in pairs])
    sp = SpectralPhase(M)
    assert sp.k > 0 and sp.max_rate > 1e6
    spectral = sp.product_integrals(sp.project(rows), [(x0, h)], pairs)
    van_loan = impact_run.ExpmForm(M).product_integrals(rows, [(x0, h)], pairs)
    scale = np.abs(want).max()
    np.testing.assert_allclose(spectral, want, rtol=1e-9, atol=1e-11 * scale)
    np.testing.assert_allclose(van_loan, want, rtol=1e-9, atol=1e-11 * scale)
    # two runs add up
    twice = sp.product_integrals(sp.project(rows), [(x0, h), (2 * x0, h)], pairs)
    np.testing.assert_allclose(twice, 5 * spectral, rtol=1e-12)


@pytest.mark.parametrize("contact", ["rigid", "spring"])
def test_compiled_and_matrix_exponential_paths_agree(monkeypatch, contact):
    """The compiled search and the matrix-exponential fallback apply the same rules."""
    bodies = (Body(LumpedMass(0.5), velocity=1.0),
              Body(Rod(1.0, 1.0, support="fixed").modal_model(12, residual=True)))
    law = Rigid() if contact == "rigid" else LinearSpring(2e4)
    # events do not depend on the output step: a coarse one keeps the expm path quick
    fast = solve_impact(*bodies, contact=law, t_end=6.0, dt=0.05, method="laplace")
    monkeypatch.setattr(impact_run, "_phase_form",
                        lambda M, update_of=None: impact_run.ExpmForm(M))
    slow = solve_impact(*bodies, contact=law, t_end=6.0, dt=0.05, method="laplace")
    assert any("matrix-exponential" in note for note in slow.notes)
    assert len(fast.contact_intervals) == len(slow.contact_intervals) > 1
    assert np.allclose(fast.contact_intervals, slow.contact_intervals, rtol=0, atol=1e-11)
    assert fast.restitution == pytest.approx(slow.restitution, rel=1e-10)



def test_phase_run_start_tolerance_covers_the_rounding_of_a_cancelling_row():
    """An event row that projects on the modes with cancellation (a stiff contact's force
    row: large entries, a small value) is evaluated with rounding far above ``1e-12`` of
    its terms. At a phase start where the row is zero and rising, that rounding must not
    read as an event at once (it did: a contact ended at its start, again and again)."""
    rng = np.random.default_rng(6)
    blocks = np.zeros((6, 6))
    for i, (sigma, omega) in enumerate([(-2.0, 300.0), (-5.0, 1100.0), (-30.0, 4000.0)]):
        blocks[2 * i:2 * i + 2, 2 * i:2 * i + 2] = [[sigma, omega], [-omega, sigma]]
    T = rng.normal(size=(6, 6))
    T[1] = T[0] + 1e-5 * rng.normal(size=6)      # states 0 and 1 move almost together
    M = T @ blocks @ np.linalg.inv(T)
    x = rng.normal(size=6)
    x[1] = x[0]                                  # the row is exactly zero at the start
    row = np.array([1.0, -1.0, 0.0, 0.0, 0.0, 0.0])
    if row @ M @ x < 0:
        row = -row                               # ... and rising
    sp = SpectralPhase(M)
    pe, ee = sp.project(row)
    coefficients = sp.output_coefficients(row, sp.coordinates(x))
    total = np.abs(coefficients[1]).sum() + np.abs(coefficients[0]).sum()
    # the closed form's rounding at the start is some 1e-11 to 1e-10 of its terms, of
    # either sign by machine and library: the start is set below zero by that much
    # (rows of 0 and 1 differ by it), as the rounding leaves it on some machines
    x[1] = x[0] + 3e-10 * total * row[0]         # row[0] = +-1: row @ x = -3e-10 total
    coefficients = sp.output_coefficients(row, sp.coordinates(x))
    e0 = sp.evaluate(coefficients, [0.0])[0, 0]
    assert -1e-9 * total < e0 < -1e-12 * total
    abs_r = np.abs(sp.rates)
    order = np.argsort(-abs_r, kind="stable").astype(np.int64)
    tau = phase_run(sp.rates, abs_r, abs_r**4, order, sp._modes.real.copy(),
                    sp._modes.imag.copy(), sp._proj.real.copy(), sp._proj.imag.copy(), sp.in0,
                    sp._s0_powers, pe, ee, pe, ee, np.abs(row) @ np.abs(sp._modes), x, 0.0,
                    0.01, 1e-3, 1e-12, True, True)[0]

    def closed_form(t):      # the phase's own closed form: its first genuine zero
        return sp.evaluate(coefficients, [t])[0, 0]

    grid = np.linspace(0.0, 0.01, 4001)[1:]
    values = sp.evaluate(coefficients, grid)[0]
    first_negative = grid[np.argmax(values < -1e-9 * np.max(np.abs(values)))]
    assert values[0] > 0.0 and first_negative > 1e-3
    want = brentq(closed_form, first_negative - grid[0], first_negative, xtol=1e-16)
    assert tau == pytest.approx(want, rel=1e-9)


def test_the_matrix_exponential_form_evaluates_times_by_kept_steps_as_by_expm():
    """:class:`ExpmForm` evaluates evenly spaced times (the event search's chunks, each
    starting where the last ended) by products with a kept ``e^(M h)``; single times
    (a root finder's) from the start itself. Both agree with one ``expm`` per time on a
    stable, non-normal matrix, in any order of the times asked for."""
    rng = np.random.default_rng(3)
    n = 12
    M = rng.normal(size=(n, n)) - 4.0 * np.eye(n)
    M[0, 1] += 50.0                                   # non-normal
    x, rows = rng.normal(size=n), rng.normal(size=(2, n))
    form = impact_run.ExpmForm(M)
    step = 0.01
    for start in (0.0, 32 * step):                    # two chunks, the second continuing
        taus = start + step * np.arange(1, 33)
        got = form.evaluate_orders((rows, x), taus, (0, 1))
        for d, values in zip((0, 1), got):
            want = np.column_stack([rows @ np.linalg.matrix_power(M, d)
                                    @ scipy.linalg.expm(M * t) @ x for t in taus])
            np.testing.assert_allclose(values, want, rtol=1e-12, atol=1e-12 * abs(want).max())
    shuffled = rng.permutation(step * np.arange(1, 20))
    want = np.column_stack([rows @ scipy.linalg.expm(M * t) @ x for t in shuffled])
    np.testing.assert_allclose(form.evaluate((rows, x), shuffled), want, rtol=1e-12,
                               atol=1e-12 * abs(want).max())
    assert form.scalar((rows[:1], x), 0.123) == pytest.approx(
        float(rows[0] @ scipy.linalg.expm(M * 0.123) @ x), rel=1e-14)
