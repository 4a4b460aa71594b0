"""continue_above_band: exact answers on uniform rods (G = T/m; fixed rod e = 0.6989; two
equal free rods: a rectangular force Z v high and 2T long, e = 1)."""

import warnings

import numpy as np
import pytest
from scipy.integrate import trapezoid

from data_synth import CantileverBeam, LumpedMass, Rod, lightly_damped
from data_synth.reference_impacts import mass_on_fixed_rod
from impactpred import Body, solve_impact
from impactpred.truncation import (
    NoComplianceAbove,
    continue_above_band,
    high_frequency_conductance,
    identified_model,
    impact_figures,
    pattern_share,
    smooth_tail_design,
)

EXACT_E = 0.698876  # mass M = m on a fixed rod, all contacts (reference_impacts)


def _band_top(n, T=1.0):
    """Midway between fixed-rod modes n and n+1 (Hz)."""
    return n / (2 * T)


@pytest.mark.parametrize("n", [10, 20])
@pytest.mark.parametrize("mass, T", [(1.0, 1.0), (2.5, 0.3)])
def test_conductance_is_the_rod_admittance(n, mass, T):
    model = Rod(mass, T, support="fixed").modal_model(n, residual=True)
    G, _omega_top, dw, mk = high_frequency_conductance(model, _band_top(n, T))
    assert G == pytest.approx(T / mass, rel=1e-12)
    assert dw == pytest.approx(np.pi / T) and mk == pytest.approx(mass / 2)
    out = continue_above_band(model, _band_top(n, T))
    # the impulse response starts at h(0+) = T/m, as the rod's square wave
    assert out.impulse_response(np.array([0.0]))[0] == pytest.approx(T / mass, rel=1e-9)


@pytest.mark.parametrize("extend", [1.0, 4.0])
def test_passive_and_static_flexibility_kept(extend):
    model = Rod(1.0, 1.0, support="fixed").modal_model(10, residual=True)
    out = continue_above_band(model, _band_top(10), extend=extend)
    assert out.is_passive()
    assert out.flexibility >= 0 and np.all(out.real_residues > 0)
    assert out.static_flexibility() == pytest.approx(model.static_flexibility(), rel=1e-9)


def test_in_band_frf_changes_little_and_gets_closer_to_the_rod():
    rod = Rod(1.0, 1.0, support="fixed")
    model = rod.modal_model(10, residual=True)
    out = continue_above_band(model, _band_top(10))
    wn = np.abs(model.poles)
    w = np.linspace(0.05, 10 * np.pi, 3000)
    w = w[np.min(np.abs(w[:, None] - wn[None]), axis=1) > 0.05]   # off the undamped peaks
    h0, h1, exact = model.frf(w), out.frf(w), rod.frf(w)
    assert np.median(np.abs(h1 - h0) / np.abs(h0)) < 0.05
    assert np.median(np.abs(h1 - exact) / np.abs(exact)) < 0.5 * np.median(
        np.abs(h0 - exact) / np.abs(exact))


@pytest.mark.parametrize("n", [5, 10, 20])
def test_mass_on_fixed_rod_restitution(n):
    model = Rod(1.0, 1.0, support="fixed").modal_model(n, residual=True)
    mass = Body(LumpedMass(1.0), velocity=1.0)
    plain = solve_impact(mass, Body(model), t_end=12.0, method="laplace")
    cont = solve_impact(mass, Body(continue_above_band(model, _band_top(n))), t_end=12.0,
                        method="laplace")
    # the continued model no longer chatters and keeps e within 0.5 % of the continuum
    assert cont.n_contacts < plain.n_contacts
    assert cont.restitution == pytest.approx(EXACT_E, rel=5e-3)
    assert cont.restitution < 1.0
    first = impact_figures(cont, resolution=0.5 / _band_top(n))
    if n >= 10:
        assert first["contact_duration"] == pytest.approx(3.067668, rel=0.02)


def test_no_upper_flexibility_warns_and_stays_passive():
    model = Rod(1.0, 1.0, support="fixed").modal_model(10, residual=False)
    with pytest.warns(RuntimeWarning, match="no upper residual flexibility"):
        out = continue_above_band(model, _band_top(10))
    assert out.is_passive()


def test_rejects_non_modal_models():
    with pytest.raises(TypeError):
        continue_above_band(Rod(1.0, 1.0), 5.0)


# ------------------------------------------------------------------ the smooth tail
def _free_rod_truth(n=10, mass=1.0, T=1.0):
    """The benchmark's damped truth of a free rod: first n modes + residual, band top (Hz)."""
    truth = lightly_damped(Rod(mass, T), n + 10, 0.001)
    w = np.sort(truth.modes["omega_n"].to_numpy())
    w = w[w > 0]
    return truth.truncate(n, residual=True), 0.5 * (w[n - 1] + w[n]) / (2 * np.pi)


def test_smooth_tail_design_is_passive_and_exact_in_h0_and_compliance():
    d = smooth_tail_design(4.0)
    assert d.error < 0.015                     # max |h/G - (1 - (2/pi) Si(x))|
    assert min(d.weights) >= 0 and all(c > 0 for _, _, c in d.modes)
    assert all(c > 0 and s > 0 for s, c in d.poles)
    assert sum(c for _, c in d.poles) == pytest.approx(1.0, rel=1e-12)     # h(0+) = G
    assert d.compliance() == pytest.approx(2 / np.pi, rel=1e-6)           # 2G/(pi w_a)
    # the solver's cost: nothing above about 9 omega_a
    assert max(max(s for s, _ in d.poles), max(u for u, _, _ in d.modes)) < 9.0


def test_smooth_tail_keeps_h_flat_after_the_jump():
    """Free rod, 10 modes: h = T/m on (0, 2T); the single pole dips to 0.76 T/m."""
    model, top = _free_rod_truth()
    t = np.linspace(1e-6, 1.9, 20000)
    smooth = continue_above_band(model, top)
    pole = continue_above_band(model, top, tail="pole")
    assert np.max(np.abs(smooth.impulse_response(t) - 1.0)) < 0.03
    assert np.max(np.abs(pole.impulse_response(t) - 1.0)) > 0.2
    assert smooth.is_passive() and np.all(smooth.real_residues > 0)
    assert smooth.static_flexibility() == pytest.approx(model.static_flexibility(), rel=1e-9)
    assert smooth.impulse_response(np.array([0.0]))[0] == pytest.approx(1.0, rel=1e-9)


def test_equal_rods_peak_within_10_percent_of_Zv():
    """Paper case a from a truth continued at 10 modes: a rectangle Z v high, 2T long, e = 1.

    The single real pole overshoots the height by 30 %; the smooth tail by 0.2 %.
    """
    model, top = _free_rod_truth()
    figures = {}
    for tail in ("smooth", "pole"):
        cont = continue_above_band(model, top, tail=tail)
        res = solve_impact(Body(cont, velocity=1.0), Body(cont, velocity=-1.0), t_end=6.0,
                           method="laplace")
        figures[tail] = impact_figures(res, resolution=0.5 / top)
    smooth = figures["smooth"]
    assert smooth["peak_force"] == pytest.approx(1.0, rel=0.05)       # Z v = (m/T) v = 1 N
    assert smooth["contact_duration"] == pytest.approx(2.0, rel=0.02)
    assert smooth["impulse"] == pytest.approx(2.0, rel=0.01)
    assert smooth["restitution"] == pytest.approx(1.0, rel=0.015)
    assert smooth["restitution"] >= figures["pole"]["restitution"] - 1e-3
    assert figures["pole"]["peak_force"] > 1.25


def test_thinning_modes_are_continued_along_their_pattern():
    """A cantilever's modes above the band continue the top modes' pattern (spacing
    growing like sqrt(omega)): the synthesized modes fall on the exact beam's next modes,
    at its modal mass, the real pole carries the rest of their compliance and the static
    flexibility is kept."""
    beam = CantileverBeam(10.0, 4.0)
    model = beam.modal_model(10, residual=True)
    exact = beam.modal_model(60)
    w = np.sort(exact.modes["omega_n"].to_numpy())
    top_hz = 0.5 * (w[9] + w[10]) / (2 * np.pi)
    out, info = continue_above_band(model, top_hz, return_info=True)
    assert info.tail == "pattern" and 0.0 < info.scale < 1.0
    synthesized = np.sort(out.modes["omega_n"].to_numpy())[10:]
    assert synthesized.size == 30                 # up to 16 times the band top
    assert synthesized == pytest.approx(w[10:40], rel=3e-3)
    assert out.modes["modal_mass"].to_numpy() == pytest.approx(2.5, rel=1e-12)
    assert out.is_passive() and np.all(out.real_residues > 0)
    assert out.static_flexibility() == pytest.approx(model.static_flexibility(), rel=1e-6)
    # the pole's compliance is the exact beam's modes beyond the synthesized ones
    beyond = model.flexibility - float(np.sum(1.0 / (2.5 * synthesized**2)))
    assert info.scale * info.conductance / info.sigma == pytest.approx(beyond, rel=0.02)
    assert out.impulse_response(np.array([0.0]))[0] == pytest.approx(
        info.scale * info.conductance, rel=1e-9)


@pytest.mark.parametrize("n", [5, 10, 20, 40])
def test_pattern_share_is_the_omitted_modes_compliance(n):
    """The top modes' pattern gives the compliance of the modes above the band: exactly
    the uniform continuum's for a rod, a beam's sum over k > n (to 0.3 % at 5 modes)."""
    beam = CantileverBeam(10.0, 4.0)
    exact = beam.modal_model(n + 1, residual=True)
    w = np.sort(exact.modes["omega_n"].to_numpy())
    top_hz = 0.5 * (w[n - 1] + w[n]) / (2 * np.pi)
    model = beam.modal_model(n, residual=True)
    G, omega_top, dw, mk = high_frequency_conductance(model, top_hz)
    omega_a = omega_top + 0.5 * dw
    continuum = 2.0 * G / (np.pi * omega_a)
    share = pattern_share(w[n - 3:n], omega_a, dw)
    # the omitted modes' compliance of the exact beam: its residual flexibility
    assert share == pytest.approx(model.flexibility / continuum, rel=5e-3)
    assert 0.4 < share < 2.0 / 3.0
    rod = Rod(1.0, 1.0).modal_model(n + 1)
    wr = np.sort(rod.modes["omega_n"].to_numpy())
    assert pattern_share(wr[-3:], wr[-1] + np.pi / 2, np.pi) == 1.0
    assert pattern_share(wr[-2:], wr[-1] + np.pi / 2, np.pi) == 1.0     # < 3 modes


def test_short_upper_flexibility_keeps_the_tail_and_its_h0():
    """A fit whose upper residual flexibility is 8 % short (noise) no longer scales the
    tail's conductance down (h(0+) stays G, no dip after it): the static flexibility
    grows by the shortfall instead."""
    model, top = _free_rod_truth(n=20)
    short = model.replace(flexibility=0.92 * model.flexibility)
    out, info = continue_above_band(short, top, return_info=True)
    ref = continue_above_band(model, top)
    assert info.scale == 1.0
    t = np.linspace(1e-5, 1.9, 20000)
    assert out.impulse_response(np.array([0.0]))[0] == pytest.approx(1.0, rel=1e-3)
    assert np.max(np.abs(out.impulse_response(t) - ref.impulse_response(t))) < 1e-3
    assert np.min(out.impulse_response(t)) > 0.97
    mass = Body(LumpedMass(1.0), velocity=1.0)
    fixed = Rod(1.0, 1.0, support="fixed").modal_model(20, residual=True)
    out_f = continue_above_band(fixed.replace(flexibility=0.92 * fixed.flexibility),
                                _band_top(20))
    assert out_f.static_flexibility() == pytest.approx(fixed.static_flexibility(), rel=1e-3)
    res = solve_impact(mass, Body(out_f), t_end=12.0, method="laplace")
    first = impact_figures(res, resolution=0.5 / _band_top(20))
    grid = np.linspace(0.0, 12.0, 20001)
    exact = mass_on_fixed_rod(1.0, 1.0, 1.0, 1.0, grid)
    peak = float(np.max(exact.force[grid <= exact.separation_time]))
    # within 5 % (the tail scaled to 0.92 G: +9 %)
    assert first["peak_force"] == pytest.approx(peak, rel=0.05)
    assert res.restitution == pytest.approx(EXACT_E, rel=5e-3)


def test_tail_extent_holds_the_synthesized_modes_to_sqrt_n():
    from impactpred.truncation import tail_extent

    assert tail_extent(5) == tail_extent(10) == 16.0
    assert tail_extent(40) == pytest.approx(8.0, rel=1e-12)
    assert tail_extent(20) == pytest.approx(16.0 / np.sqrt(2.0), rel=1e-12)
    # synthesized modes ~ n extend: sqrt(n) growth
    assert 40 * tail_extent(40) == pytest.approx(2 * 10 * tail_extent(10), rel=1e-12)


def test_unknown_tail_is_rejected():
    model, top = _free_rod_truth()
    with pytest.raises(ValueError, match="tail"):
        continue_above_band(model, top, tail="spline")


@pytest.mark.parametrize("extend", [float("nan"), float("inf"), 0.0, -2.0])
def test_bad_extend_is_rejected_by_name(extend):
    model, top = _free_rod_truth()
    with pytest.raises(ValueError, match="extend"):
        continue_above_band(model, top, extend=extend)
    with pytest.raises(ValueError, match="extend"):
        smooth_tail_design(extend)


def test_smooth_tail_design_needs_two_nodes():
    with pytest.raises(ValueError, match="n_nodes"):
        smooth_tail_design(4.0, n_nodes=1)


def _pulses(*spans):
    """A result-like object whose force is a half-sine of height h on each (a, b, h)."""
    from types import SimpleNamespace

    t = np.linspace(0.0, 4.0, 40001)
    force = np.zeros_like(t)
    for a, b, h in spans:
        inside = (t >= a) & (t <= b)
        force[inside] = h * np.sin(np.pi * (t[inside] - a) / (b - a))
    return SimpleNamespace(t=t, force=force, contact_intervals=tuple((a, b) for a, b, _ in spans),
                           impulse=float(trapezoid(force, t)), restitution=0.5)


def test_impact_figures_ringing_after_separation_is_not_contact():
    # a contact, then two slivers of ringing within the resolution: the duration stays
    ringing = _pulses((0.0, 1.0, 1.0), (1.02, 1.03, 0.01), (1.05, 1.08, 0.02))
    figs = impact_figures(ringing, resolution=0.1)
    assert figs["contact_duration"] == pytest.approx(1.0)
    assert (figs["n_contacts"], figs["n_contacts_raw"]) == (1, 3)
    # a dip of the force: slivers followed by the contact's larger rest are one contact
    dip = _pulses((0.0, 1.0, 1.0), (1.02, 1.03, 0.01), (1.05, 1.6, 0.8))
    figs = impact_figures(dip, resolution=0.1)
    assert figs["contact_duration"] == pytest.approx(1.6)
    assert figs["n_contacts"] == 1
    # a re-contact beyond the resolution is a contact of its own, small or not
    later = _pulses((0.0, 1.0, 1.0), (1.5, 1.51, 0.01))
    figs = impact_figures(later, resolution=0.1)
    assert (figs["contact_duration"], figs["n_contacts"]) == (pytest.approx(1.0), 2)
    # slivers bridge a dip for one period of the band top (2 resolutions), no longer
    chain = _pulses((0.0, 1.0, 1.0), (1.08, 1.09, 0.01), (1.16, 1.17, 0.01),
                    (1.24, 1.25, 0.01), (1.32, 1.33, 0.01), (1.40, 1.8, 0.8))
    figs = impact_figures(chain, resolution=0.1)
    assert figs["contact_duration"] == pytest.approx(1.0)
    assert (figs["n_contacts"], figs["n_contacts_raw"]) == (2, 6)
    # a long train of slivers, each close to the one before, stays ringing: one contact
    train = _pulses((0.0, 1.0, 1.0), *[(1.0 + 0.05 * k, 1.01 + 0.05 * k, 0.002)
                                       for k in range(1, 11)])
    figs = impact_figures(train, resolution=0.06)
    assert (figs["contact_duration"], figs["n_contacts"]) == (pytest.approx(1.0), 1)
    # ringing_share = 0 merges every interval within the resolution (the old rule)
    assert impact_figures(ringing, resolution=0.1,
                          ringing_share=0.0)["contact_duration"] == pytest.approx(1.08)


def test_identified_model_as_normal_modes_has_no_spurious_h0():
    """The identified residues' real parts (noise) would give h(0+) != 0: dropped inside
    the band; the pseudo-modes above it become normal modes of the same static compliance
    (a real residue is not a passive term); kept with normal_modes=False."""
    from modalid import FRFData, ModalFit

    truth = lightly_damped(Rod(1.0, 1.0, support="fixed"), 14, 0.001)
    freq = np.linspace(0.02, 4.0, 2000)
    rng = np.random.default_rng(3)
    h = truth.frf(2 * np.pi * freq)
    h = h * (1 + 0.01 * (rng.standard_normal(h.size) + 1j * rng.standard_normal(h.size)))
    fit = ModalFit().fit(FRFData(freq, h))
    raw = identified_model(fit, continuation=False, normal_modes=False)
    normal = identified_model(fit, continuation=False)
    top = 2 * np.pi * fit.report_["band_hz"][1]
    inside = np.abs(raw.poles) <= top
    assert abs(2 * np.sum(raw.residues[inside].real)) > 1e-6     # noise leaves some
    assert np.all(normal.residues[inside].real == 0.0)
    np.testing.assert_array_equal(normal.residues[inside].imag, raw.residues[inside].imag)
    above = np.abs(raw.poles) > top
    assert above.any() and np.all(normal.residues[above].real == 0.0)
    assert np.all(normal.residues[above].imag <= 0.0)
    np.testing.assert_allclose((normal.residues[above] / normal.poles[above]).real,
                               (raw.residues[above] / raw.poles[above]).real, rtol=1e-12)
    np.testing.assert_array_equal(normal.residues[~inside & ~above],
                                  raw.residues[~inside & ~above])
    assert raw is fit.model_


def test_identified_model_folds_a_multi_output_fits_pseudo_modes():
    """A cantilever fitted at three points with common poles: the pseudo-modes above the
    band leave as static compliance in every row's constant, close to the exact model's
    compliance of its modes above the band; nothing moves at t = 0; no continuation."""
    import warnings

    from data_synth import CantileverBeam, LumpedMass, synthetic_frf
    from impactpred import Body, solve_impact
    from modalid import FRFSet, ModalFit

    beam = CantileverBeam(1.0, 1.0)
    xi = [0.0, 0.5, 0.8]
    truth = beam.multi_output_model(xi, 18, damping_ratio=0.01, residual=True)
    freq_hz = np.linspace(0.05, 80.0, 3000)
    frfs = [synthetic_frf(truth.row(i), freq_hz, noise=0.01, seed=i) for i in range(3)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit().fit(FRFSet.from_frfs(frfs, driving_point=0, outputs=truth.outputs))
    model = identified_model(fit, continuation=False)
    top = 2 * np.pi * fit.report_["band_hz"][1]
    assert np.all(np.abs(model.poles) <= top) and np.all(model.residues.real == 0)
    above = np.abs(truth.poles) > top
    exact = truth.flexibility - 2 * np.sum((truth.residues[:, above]
                                            / truth.poles[above]).real, axis=1)
    np.testing.assert_allclose(model.flexibility, exact, rtol=0.15)
    res = solve_impact(Body(LumpedMass(0.1), velocity=1.0), Body(model), t_end=0.5)
    assert abs(res.force[0]) < 1e-9 * np.max(res.force)
    assert np.max(np.abs(res.points[1].displacement[:, 0])) < 1e-15
    with pytest.raises(ValueError, match="continuation=False"):
        identified_model(fit)


def test_a_weakly_coupled_mode_stays_out_of_the_top_modes_pattern():
    """A noise pole of large modal mass between the top modes (a steel beam's fit at 5 %
    noise: 41 kg for 0.39) changes neither the conductance nor the continuation's pattern;
    it stays in the model."""
    from modalid import ModalModel

    from impactpred.truncation import continue_above_band

    w = 2 * np.pi * np.arange(1, 11)
    clean = ModalModel.from_modes(w, 1e-3, 0.5)
    weak = ModalModel.from_modes(np.r_[w, 2 * np.pi * 9.6], 1e-3, np.r_[[0.5] * 10, 50.0])
    top_hz = 10.5
    assert high_frequency_conductance(weak, top_hz) == pytest.approx(
        high_frequency_conductance(clean, top_hz), rel=1e-12)
    assert high_frequency_conductance(clean, top_hz)[0] == pytest.approx(
        np.pi / (2 * 0.5 * 2 * np.pi), rel=1e-12)
    a, b = (continue_above_band(m, top_hz, extend=4.0) for m in (clean, weak))
    assert len(b.poles) == len(a.poles) + 1
    assert np.sort(np.abs(b.poles))[-1] == pytest.approx(np.sort(np.abs(a.poles))[-1])


@pytest.mark.parametrize("noise", [0.0, 0.03])
def test_a_band_with_no_compliance_above_it_is_not_continued(noise):
    """A spring-mass's accelerance to 2.6 times its mode: above the mode the band is the
    mass line, and its fit has no upper residual flexibility (0 to 1e-4 of the
    continuation's compliance). Continued as a continuum it had given a 0.42 kg mass's
    Hertz impact a restitution of 0.135 for the exact 0.622; it is refused by name.
    A cantilever cut below its second mode, whose band does show the modes above it
    (upper residual flexibility 4.5 % of that compliance), is continued."""
    from data_synth import SpringMass, synthetic_frf
    from modalid import ModalFit

    def fitted(truth, top_hz):
        freq = np.linspace(top_hz / 2000, top_hz, 2000)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return ModalFit().fit(synthetic_frf(truth, freq, quantity="accelerance",
                                                noise=noise, seed=39))

    spring_mass = lightly_damped(SpringMass(1.773799480628025, 920663.2681301013), 1, 3e-4)
    fit = fitted(spring_mass, 297.7377776232762)
    with pytest.raises(NoComplianceAbove, match="no compliance above"):
        identified_model(fit)
    kept = identified_model(fit, continuation=False, upper_residual=True)
    assert kept.n_modes == fit.model_.n_modes
    # by default the terms above the band, noise there, are dropped
    bare = identified_model(fit, continuation=False)
    assert bare.flexibility == 0.0 and bare.n_modes == 1
    assert bare.modes["frequency_hz"][0] == pytest.approx(114.66, rel=1e-3)
    assert bare == identified_model(fit, continuation=False, upper_residual=False)
    with pytest.raises(ValueError, match="upper_residual=False needs continuation=False"):
        identified_model(fit, upper_residual=False)
    beam = lightly_damped(CantileverBeam(1.0, 1.0), 300, 1e-3)
    fit = fitted(beam, 2.6 * beam.modes["frequency_hz"][0])
    assert fit.report_["n_modes"] == 1
    assert identified_model(fit).n_modes > 1                # continued
    kept = identified_model(fit, continuation=False)        # its upper terms kept
    top = 2 * np.pi * fit.report_["band_hz"][1]
    assert kept.flexibility > 0 or np.any(np.abs(kept.poles) > top)


def test_cancelling_pseudo_modes_above_the_band_keep_their_net_static_compliance():
    """Two pseudo-modes at one frequency above the band with residues +-106 (a fixed rod
    refitted on 80 % of its band): static compliances +0.206 and -0.202 m/N. Made normal
    modes, they keep the net 0.004 m/N (the negative one clipped alone had left 0.206, and
    the impact's restitution 0.861 for 0.698); a mode inside the band keeps its mass."""
    from impactpred._continuation import static_compliance
    from impactpred.truncation import _normal_residues
    from modalid import ModalModel

    w = 2 * np.pi * 8.459
    pole = w * (-0.051 + 1j * np.sqrt(1 - 0.051**2))
    inside = 2 * np.pi * 2.0 * (-0.01 + 1j)
    model = ModalModel(poles=[inside, pole, pole * (1 + 1e-9)],
                       residues=[-0.02j, -106.294 - 0.0912j, 106.311 - 0.0199j])
    before = static_compliance(model.poles[1:], model.residues[1:])
    assert before[0] < -0.2 and before[1] > 0.2
    residues, flexibility = _normal_residues(model, band_top_hz=8.0)
    after = static_compliance(model.poles[1:], residues[1:])
    assert np.all(residues.real == 0) and residues[0] == -0.02j and flexibility == 0.0
    assert after.sum() == pytest.approx(before.sum(), rel=1e-9)
    assert after[0] == 0.0 and 0.0 < after[1] < 0.01
    # every term positive: unchanged
    single = ModalModel(poles=[pole], residues=[-0.2j * abs(pole)], flexibility=1e-3)
    residues, flexibility = _normal_residues(single, 8.0)
    assert static_compliance(single.poles, residues) == pytest.approx(
        static_compliance(single.poles, single.residues))
    assert flexibility == 1e-3
    # a pseudo-mode cancelling most of the flexibility: their net 0.01 m/N is kept, not 0.2
    against = ModalModel(poles=[pole], residues=[0.19 * abs(pole) ** 2 / (2 * pole.imag) * 1j],
                         flexibility=0.2)
    assert static_compliance(against.poles, against.residues) == pytest.approx([-0.19])
    residues, flexibility = _normal_residues(against, 8.0)
    assert residues[0] == 0 and flexibility == pytest.approx(0.01)
