"""Output points: displacement, velocity and acceleration histories away from the contact."""

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pandas as pd
import pytest
import scipy.signal

from data_synth import CantileverBeam, LumpedMass, Rod, SpringMass
from impactpred import Body, LinearSpring, PointResponse, SampledResponse, solve_impact
from modalid import ModalModel, MultiOutputModalModel


def _structure(flexibility=(2e-4, 0.0, 2e-4)):
    """A free, lightly damped 2-mode structure; row 0 is the driving point, row 2 a copy of it."""
    poles = np.array([-0.3 + 40j, -0.5 + 110j])
    residues = np.array([[-0.05j, -0.03j], [0.001 - 0.02j, 0.04j], [-0.05j, -0.03j]])
    return MultiOutputModalModel(poles=poles, residues=residues, inverse_mass=[0.5, -0.2, 0.5],
                                 flexibility=list(flexibility), outputs=["drv", "b", "copy"],
                                 driving_point=0)


def _far_from(t, events, distance):
    events = np.asarray(events, dtype=float)
    return np.min(np.abs(t[:, None] - events[None, :]), axis=1) > distance


# ---------------------------------------------------------------- (1) driving row = y
@pytest.mark.parametrize("method", ["laplace", "modal", "convolution"])
def test_driving_row_output_equals_contact_displacement(method):
    multi = _structure()
    dt = 1e-3 if method == "laplace" else 1e-4
    # the structure as body 1 (force -f) and as body 2 (force +f), with vibration
    for flip in (False, True):
        mass = Body(LumpedMass(1.0), velocity=-1.0 if flip else 1.0)
        struct = Body(multi, vibration=[[1e-3, 0.0]])
        bodies = (struct, mass) if flip else (mass, struct)
        # a clearance that covers the vibration's 1 mm, so that they do not start overlapping
        res = solve_impact(*bodies, gap=2e-3, t_end=0.2, dt=dt, method=method)
        i = 0 if flip else 1
        points = res.points[i]
        assert res.points[1 - i] is None
        assert isinstance(points, PointResponse)
        assert points.labels == ("drv", "b", "copy")
        y = res.y1 if flip else res.y2
        scale = float(np.max(np.abs(y)))
        for row in (0, 2):
            np.testing.assert_allclose(points.displacement[row], y, rtol=0, atol=1e-12 * scale)
        np.testing.assert_array_equal(points.velocity[0], points.velocity[2])
        assert res.n_contacts >= 1


# --------------------------------------------------- (2) exact against lsim and modal
def test_laplace_outputs_match_lsim_of_the_multi_output_state_space():
    multi = _structure()
    dt = 2e-6
    res = solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(multi), t_end=0.05, dt=dt,
                       method="laplace")
    assert not res.dirac_impulses
    # the exact force on the uniform grid (event times dropped) drives lsim (first-order hold)
    k = np.round(res.t / dt)
    on_grid = np.abs(res.t - k * dt) < 1e-12
    _, first = np.unique(k[on_grid], return_index=True)
    pick = np.flatnonzero(on_grid)[first]
    t, f = res.t[pick], res.force[pick]
    A, b, C, d = multi.statespace_matrices()
    _, y_ref, X = scipy.signal.lsim(scipy.signal.StateSpace(A, b[:, None], C, d[:, None]), f, t)
    p = res.points[1]
    disp, vel, acc = (getattr(p, q)[:, pick] for q in ("displacement", "velocity",
                                                       "acceleration"))
    scale = np.max(np.abs(disp), axis=1, keepdims=True)
    assert np.max(np.abs(disp - y_ref.T) / scale) < 1e-7
    # velocity and acceleration from the lsim states; f', f'' by differences (kinks excluded)
    f1 = np.gradient(f, dt)
    v_ref = C @ (A @ X.T + np.outer(b, f)) + np.outer(d, f1)
    a_ref = C @ (A @ A @ X.T + np.outer(A @ b, f) + np.outer(b, f1)) + np.outer(d, np.gradient(
        f1, dt))
    far = _far_from(t, [x for iv in res.contact_intervals for x in iv], 3 * dt)
    for got, ref, tol in ((vel, v_ref, 1e-7), (acc, a_ref, 1e-6)):
        scale = np.max(np.abs(got), axis=1, keepdims=True)
        assert np.max(np.abs(got - ref)[:, far] / scale) < tol
    # inside the first contact the velocity integrates to the displacement (trapezoid, O(dt^2))
    start, end = res.contact_intervals[0]
    inside = np.flatnonzero((t > start + 3 * dt) & (t < end - 3 * dt))
    a, z = inside[0], inside[-1]
    integral = np.trapezoid(vel[:, a:z + 1], dx=dt, axis=1)
    np.testing.assert_allclose(integral, disp[:, z] - disp[:, a], rtol=1e-7)


def test_laplace_outputs_agree_with_modal_stepping():
    multi = _structure()
    exact = solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(multi), t_end=0.012,
                         dt=1e-4, method="laplace")
    errors = []
    for dt in (2e-5, 1e-5):
        step = solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(multi), t_end=0.012,
                            dt=dt, method="modal")
        inside = (step.t > 20 * dt) & (step.t < 0.012 - dt)   # inside the first contact
        err = []
        for q in ("displacement", "velocity", "acceleration"):
            ref = np.array([np.interp(step.t, exact.t, row)
                            for row in getattr(exact.points[1], q)])
            got = getattr(step.points[1], q)
            err.append(np.max(np.abs(got - ref)[:, inside]) / np.max(np.abs(ref)))
        errors.append(err)
    errors = np.array(errors)
    assert np.all(errors[1] < 0.005)
    assert np.all(errors[1] < 0.7 * errors[0])     # first order in dt


# ------------------------------------------------- (3) the free rod struck by a mass
def test_free_rod_far_end_moves_at_twice_the_wave_particle_velocity():
    T, m, M, v0 = 1.0, 1.0, 0.5, 1.0
    Z = m / T
    n_T = 400
    dt = T / n_T
    res = solve_impact(Body(LumpedMass(M), velocity=v0), Body(Rod(m, T), outputs=[0, 0.5, 1]),
                       t_end=3.5 * T, dt=dt, method="convolution")
    p = res.points[1]
    assert p.labels == ("xi=0", "xi=0.5", "xi=1")
    np.testing.assert_allclose(p.displacement[0], res.y2, rtol=0, atol=1e-14)
    t, f = res.t, res.force
    n = np.arange(t.size)

    def force_before(lag):  # f(t_n - lag dt) as a left limit: the force of step n - lag - 1
        j = n - lag - 1
        return np.where(j >= 0, f[np.clip(j, 0, None)], 0.0)

    exact_force = Z * v0 * np.exp(-Z * t / M)  # the mass on a semi-infinite rod, t < 2T
    # the wave reaches xi at xi T; the far end reflects it (doubling the velocity) and the
    # reflection reaches xi at (2 - xi) T; the next arrival at the far end is at 3T
    for row, delay, until, factor in ((2, n_T, 3 * T, 2.0), (1, n_T // 2, 1.5 * T, 1.0)):
        xi_T = delay * dt
        still = t <= xi_T
        assert np.max(np.abs(p.displacement[row][still])) < 1e-14
        assert np.max(np.abs(p.velocity[row][still])) < 1e-14
        window = (t > xi_T) & (t <= until)
        # exact for the discrete (piecewise-constant) force ...
        np.testing.assert_allclose(p.velocity[row][window],
                                   factor * force_before(delay)[window] / Z, rtol=0, atol=1e-13)
        # ... and to discretisation accuracy for the continuum's exponential force
        ref = factor * np.interp(t - xi_T, t, exact_force) / Z
        assert np.max(np.abs(p.velocity[row][window] - ref[window])) < 2 * factor * v0 * dt / M


# ------------------------------------- (4) the rod as a truncated multi-output model
def test_rod_multi_output_model_converges_to_the_exact_outputs():
    T, m, M, v0 = 1.0, 1.0, 0.5, 1.0
    rod = Rod(m, T)
    xi = [0, 0.5, 1]
    exact = solve_impact(Body(LumpedMass(M), velocity=v0), Body(rod, outputs=xi),
                         t_end=4 * T, dt=T / 2000, method="convolution")
    disp_err, vel_err = [], []
    for n in (25, 50, 100):
        res = solve_impact(Body(LumpedMass(M), velocity=v0),
                           Body(rod.multi_output_model(xi, n, residual=True)),
                           t_end=4 * T, dt=T / 200, method="laplace")
        p = res.points[1]
        assert p.labels == ("xi=0", "xi=0.5", "xi=1")
        ref = {q: np.array([np.interp(res.t, exact.t, row) for row in getattr(exact.points[1], q)])
               for q in ("displacement", "velocity")}
        disp_err.append(np.max(np.abs(p.displacement - ref["displacement"])))
        vel_err.append(np.mean(np.abs(p.velocity[2] - ref["velocity"][2])))
    assert disp_err[0] > disp_err[1] > disp_err[2] and disp_err[2] < 0.01 * v0 * T
    assert vel_err[0] > vel_err[1] > vel_err[2] and vel_err[2] < 0.05 * v0


def test_beam_outputs_and_a_clamped_end_that_stays_still():
    beam = CantileverBeam(10.0, 4.0)
    res = solve_impact(Body(Rod(1.0, 1.0), velocity=1.0),
                       Body(beam, outputs=[0.0, 0.3, 1.0]), t_end=1.0, dt=1e-3)
    p = res.points[1]
    np.testing.assert_allclose(p.displacement[0], res.y2, rtol=0,
                               atol=1e-12 * np.max(np.abs(res.y2)))
    assert np.max(np.abs(p.displacement[2])) < 1e-12 * np.max(np.abs(res.y2))
    assert np.max(np.abs(p.displacement[1])) > 0
    peaks = res.point_peaks()
    assert list(peaks.index) == [(2, "xi=0"), (2, "xi=0.3"), (2, "xi=1")]


# ---------------------------------------------------------------- result objects
def test_point_response_is_immutable_and_tabulates():
    res = solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(_structure()), t_end=0.05,
                       dt=1e-4, method="laplace")
    p = res.points[1]
    with pytest.raises(ValueError):
        p.displacement[0, 0] = 1.0
    with pytest.raises(AttributeError):
        p.labels = ()
    peaks = p.peaks()
    assert list(peaks.columns) == ["peak_displacement", "t_peak_displacement", "peak_velocity",
                                   "t_peak_velocity", "peak_acceleration",
                                   "t_peak_acceleration"]
    i = int(np.argmax(np.abs(p.velocity[1])))
    assert peaks.loc["b", "peak_velocity"] == abs(p.velocity[1, i])
    assert peaks.loc["b", "t_peak_velocity"] == p.t[i]
    frame = p.to_pandas()
    assert frame.shape == (p.t.size, 9)
    assert np.array_equal(frame[("acceleration", "b")].to_numpy(), p.acceleration[1])
    assert np.array_equal(p["drv"]["displacement"].to_numpy(), res.y2)
    ax = p.plot(quantity="velocity")
    assert len(ax.get_lines()) == 3
    with pytest.raises(ValueError):
        p.plot(quantity="jerk")
    assert isinstance(res.point_peaks(), pd.DataFrame) and len(res.point_peaks()) == 3
    plain = solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(SpringMass(1.0, 100.0)),
                         t_end=0.5, method="laplace")
    assert plain.points == (None, None) and plain.point_peaks().empty


def test_two_free_rods_with_outputs_use_the_convolution_solver():
    bodies = (Body(Rod(1.0, 1.0), velocity=1.0), Body(Rod(1.0, 1.0), outputs=[0.0, 1.0]))
    res = solve_impact(*bodies, t_end=3.0, dt=0.01)
    assert res.method == "convolution" and res.points[1] is not None
    with pytest.raises(ValueError, match="closed_form"):
        solve_impact(*bodies, t_end=3.0, dt=0.01, method="closed_form")


# -------------------------------------------------------------------- (6) bad input
def test_bad_outputs_are_rejected():
    modal = ModalModel.from_modes([10.0], 0.01, 1.0, inverse_mass=1.0)
    for model in (modal, SpringMass(1.0, 100.0), LumpedMass(1.0),
                  SampledResponse([0.0, 1.0], [1.0, 1.0])):
        with pytest.raises(TypeError, match="outputs"):
            Body(model, outputs=[0.0, 0.5])
    for xi in ([0.0, 1.5], [-0.1], [], [[0.0, 1.0]], [0.2, 0.2], [np.nan]):
        with pytest.raises(ValueError):
            Body(Rod(1.0, 1.0), outputs=xi)
    with pytest.raises(ValueError, match="outputs=None"):
        Body(_structure(), outputs=[0.0])
    poles, residues = [40j], [[-0.05j], [-0.02j]]
    with pytest.raises(ValueError):  # negative 1/M at the driving point
        Body(MultiOutputModalModel(poles=poles, residues=residues, inverse_mass=[-1.0, 0.5]))
    with pytest.raises(ValueError, match="rigid"):  # rigid motion the driving point cannot cause
        Body(MultiOutputModalModel(poles=poles, residues=residues, inverse_mass=[0.0, 0.5]))


def test_cantilever_mid_span_exact_continuum_against_a_fine_modal_sum():
    """Mid-span of a cantilever struck at the tip (spring contact, so the force is smooth).

    The exact continuum (convolution of the force with the exact transfer step response,
    first order in dt) against the Laplace solution of a 40-mode model with its residual
    transfer flexibility (exact for that model, converged in the number of modes): the
    difference is the convolution's step error, so it halves with dt.
    """
    beam, xi, contact = CantileverBeam(10.0, 4.0), [0.0, 0.5], LinearSpring(100.0)
    striker = Body(LumpedMass(1.0), velocity=1.0)
    fine = [solve_impact(striker, Body(beam.multi_output_model(xi, n, residual=True)),
                         contact=contact, t_end=1.0, dt=5e-4, method="laplace")
            for n in (20, 40)]
    modal = fine[1].points[1].displacement[1]
    scale = np.max(np.abs(modal))
    assert np.max(np.abs(fine[0].points[1].displacement[1] - modal)) < 1e-4 * scale
    errors = []
    for dt in (1e-3, 5e-4):
        exact = solve_impact(striker, Body(beam, outputs=xi), contact=contact, t_end=1.0,
                             dt=dt, method="convolution")
        mid = np.interp(fine[1].t, exact.t, exact.points[1].displacement[1])
        errors.append(np.max(np.abs(mid - modal)) / scale)
    assert errors[1] < 0.6 * errors[0] and errors[1] < 3e-3, errors


def test_rod_output_points_carry_the_pre_impact_vibration():
    """Fixed rod vibrating in its first mode (1 mm at the struck end) with points xi = 0, 0.5.

    At t = 0 the mid point is at phi_1(0.5)/phi_1(0) = cos(pi/4) of the struck end's 1 mm;
    the struck end's output is the contact displacement y2 at every sample.
    """
    rod = Rod(1.0, 1.0, support="fixed")
    res = solve_impact(Body(LumpedMass(1.0), velocity=1.0),
                       Body(rod, vibration=[[-1e-3, 0.0]], outputs=[0.0, 0.5]),
                       gap=1e-3, t_end=1.0, dt=1e-3)
    p = res.points[1]
    assert p.displacement[1, 0] == pytest.approx(-1e-3 * np.cos(np.pi / 4), rel=1e-12)
    np.testing.assert_allclose(p.displacement[0], res.y2, rtol=0, atol=1e-12)
