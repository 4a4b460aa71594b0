"""The uncertainty band (impactpred.uncertainty): the truncation estimate against a figure
of known convergence, parameter draws against the fits' scatter."""

import warnings

import numpy as np
import pytest

import impactpred.truncation
from data_synth import LumpedMass, Rod, lightly_damped
from impactpred.uncertainty import (
    perturb_poles,
    perturb_residues,
    truncation_error,
    uncertainty_band,
)
from modalid import FRFData, ModalFit


def test_the_band_lives_in_uncertainty_only():
    """No import circle: truncation (the continuation) knows nothing of the band."""
    assert not hasattr(impactpred.truncation, "uncertainty_band")


def test_truncation_error_of_a_figure_converging_like_one_over_the_band():
    limit = {"contact_duration": 2.0, "peak_force": 1.0, "impulse": 3.0, "restitution": 0.7}
    slope = {"contact_duration": 0.05, "peak_force": -0.2, "impulse": 0.01, "restitution": 0.003}

    def at(f):
        return {k: limit[k] + slope[k] / f for k in limit}

    for fraction in (0.6, 0.8):
        est = truncation_error(at(1.0), at(fraction), fraction)
        for k in limit:        # exactly the error left at the full band, |F(1) - F_inf|
            assert est[k] == pytest.approx(abs(slope[k]), rel=1e-12)
    with pytest.raises(ValueError, match="fraction"):
        truncation_error(at(1.0), at(1.0), 1.0)


def test_parameter_draws_move_the_rigid_mass_by_its_reported_std():
    truth = lightly_damped(Rod(1.0, 1.0, support="free"), 14, 0.01)
    freq = np.linspace(0.02, 4.0, 2000)
    fits = []
    for seed in range(10):
        rng = np.random.default_rng(seed)
        h = truth.frf(2 * np.pi * freq)
        h = h * (1 + 0.01 * (rng.standard_normal(h.size) + 1j * rng.standard_normal(h.size)))
        fits.append(ModalFit().fit(FRFData(freq, h)))
    # the reported std of the inverse mass is the scatter over noise draws (within 2x)
    u = np.array([f.model_.inverse_mass for f in fits])
    s_u = np.median([f.report_["inverse_mass_std"] for f in fits])
    assert 0.5 < np.std(u, ddof=1) / s_u < 2.0
    fit = fits[0]
    # with upper pseudo-modes trading against the constant its std is not reported
    assert fit.report_["upper_residual_modes"] > 0
    assert np.isnan(fit.report_["flexibility_std"])
    draws = [perturb_residues(fit, np.random.default_rng(7)) for _ in range(2)]
    assert draws[0] == draws[1]                                   # reproducible
    many = [perturb_residues(fit, np.random.default_rng(i)) for i in range(40)]
    drawn = np.array([m.inverse_mass for m in many])
    assert np.std(drawn) == pytest.approx(fit.report_["inverse_mass_std"], rel=0.35)
    assert np.all(drawn >= 0)
    assert all(m.flexibility == fit.model_.flexibility for m in many)   # NaN std: kept


def test_residue_draws_give_each_part_its_own_std():
    """A lightly damped mode's residue is nearly imaginary and so is its error: the report
    gives each part's std, and the draws use them (an even split of the complex variance
    drew the imaginary part, the modal mass, with 71 % of its std)."""
    import types

    import pandas as pd

    from modalid import ModalModel

    model = ModalModel.from_modes(2 * np.pi * np.array([3.0, 20.0]), [0.01, 0.02], [1.0, 0.5])
    re_std, im_std = np.array([1e-6, 2e-6]), np.array([4e-4, 1e-4])
    modes = pd.DataFrame({"residue_std": np.hypot(re_std, im_std),
                          "residue_real_std": re_std, "residue_imag_std": im_std})
    fit = types.SimpleNamespace(model_=model, poles_=model.poles,
                                report_={"modes": modes, "driving_point": False})
    rng = np.random.default_rng(11)
    drawn = np.array([perturb_residues(fit, rng).residues for _ in range(2000)])
    moved = drawn - model.residues
    # 2000 Gaussian draws: the sample std within 5 % of the one drawn from (4.5 sigma)
    np.testing.assert_allclose(moved.real.std(axis=0), re_std, rtol=0.05)
    np.testing.assert_allclose(moved.imag.std(axis=0), im_std, rtol=0.05)
    # without the parts' stds: half the complex variance each, as before
    fit.report_["modes"] = modes[["residue_std"]]
    rng = np.random.default_rng(11)
    even = np.array([perturb_residues(fit, rng).residues for _ in range(2000)])
    np.testing.assert_allclose((even - model.residues).imag.std(axis=0),
                               np.hypot(re_std, im_std) / np.sqrt(2), rtol=0.05)


def _measured_fixed_rod(seed=0):
    truth = lightly_damped(Rod(1.0, 1.0, support="fixed"), 20, 1e-3)
    freq = np.linspace(0.01, 5.25, 2100)                     # 10 modes in the band
    rng = np.random.default_rng(seed)
    h = truth.frf(2 * np.pi * freq)
    h = h * (1 + 0.01 * (rng.standard_normal(h.size) + 1j * rng.standard_normal(h.size)))
    return ModalFit().fit(FRFData(freq, h))


def _solve_mass_on(m1, m2):
    from impactpred import Body, solve_impact

    return solve_impact(Body(m1, velocity=1.0), Body(m2), t_end=8.0, method="laplace")


def test_pole_draws_move_frequency_and_damping_by_their_reported_std():
    """A damped spring-mass (2 Hz, zeta 0.05) at 1 % noise: the fit's reported frequency
    and damping stds are the scatter over noise draws, and the pole draws reproduce them
    (the residues, rigid mass and flexibility stay); a mass struck on it has a contact of
    about half its period, which the pole draws move more than the residue draws do (1.6
    times in every fit: the residue's imaginary part, the modal mass, sets the spring's
    stiffness too; over 2 times while the draws gave it 71 % of its std)."""
    from data_synth import SpringMass, synthetic_frf

    body = SpringMass(1.0, (2 * np.pi * 2.0) ** 2, damping_ratio=0.05)
    freq = np.linspace(0.025, 20.0, 800)
    fits = [ModalFit().fit(synthetic_frf(body, freq, noise=0.01, seed=seed))
            for seed in range(12)]
    modes = [f.report_["modes"].iloc[0] for f in fits]
    for name in ("frequency_hz", "damping_ratio"):
        scatter = np.std([m[name] for m in modes], ddof=1)
        assert 0.5 < scatter / np.median([m[f"{name}_std"] for m in modes]) < 2.0
    fit = fits[0]
    assert perturb_poles(fit, np.random.default_rng(3)) == perturb_poles(
        fit, np.random.default_rng(3))                              # reproducible
    rng = np.random.default_rng(0)
    drawn = [perturb_poles(fit, rng) for _ in range(400)]
    k = int(np.argmin(np.abs(fit.model_.poles - fit.poles_[0])))
    poles = np.array([m.poles[k] for m in drawn])
    wn, zeta = np.abs(poles), -poles.real / np.abs(poles)
    mode = fit.report_["modes"].iloc[0]
    assert np.mean(wn) / (2 * np.pi) == pytest.approx(mode["frequency_hz"], rel=1e-4)
    assert np.std(wn) / (2 * np.pi) == pytest.approx(mode["frequency_hz_std"], rel=0.15)
    assert np.mean(zeta) == pytest.approx(mode["damping_ratio"], rel=0.02)
    assert np.std(zeta) == pytest.approx(mode["damping_ratio_std"], rel=0.15)
    assert np.all(poles.real < 0) and np.all(poles.imag > 0)
    for m in drawn[:5]:
        others = np.delete(np.arange(m.poles.size), k)
        assert np.array_equal(m.poles[others], fit.model_.poles[others])
        assert np.array_equal(m.residues, fit.model_.residues)
        assert (m.inverse_mass, m.flexibility) == (fit.model_.inverse_mass,
                                                   fit.model_.flexibility)
    # a 0.5 kg mass struck on it at 1 m/s: the band's duration spread is the poles'; with
    # the residue draws alone it held all four exact figures in 10 of 20 seeds
    from impactpred import Body, solve_impact
    from impactpred.truncation import FIGURES, identified_model, impact_figures

    def solve(m1, m2):
        return solve_impact(Body(m1, velocity=1.0), Body(m2), t_end=0.6)

    exact = impact_figures(solve(LumpedMass(0.5), body))
    held = 0
    for fit in fits:
        band = uncertainty_band([LumpedMass(0.5), identified_model(fit, continuation=False)],
                                [None, fit], solve, continuation=False)
        assert band.pole_spread["contact_duration"] > 1.4 * band.spread["contact_duration"]
        held += all(band.low[k] <= exact[k] <= band.high[k] for k in FIGURES)
    assert held >= 11


def test_pole_draws_leave_an_unresolved_damping_as_fitted():
    """A fixed rod at 1 % noise whose first mode's damping the fit did not resolve: the
    draws move its frequency only (its damping std is a linearization's figure; drawn, a
    cantilever's 1e-5 +- 2.5e-3 had made a variant stick to t_end); the resolved modes'
    damping moves."""
    fit = _measured_fixed_rod()
    modes = fit.report_["modes"]
    resolved = modes["damping_resolved"].to_numpy(bool)
    assert not resolved[0] and resolved[1:].all()
    k = [int(np.argmin(np.abs(fit.model_.poles - p))) for p in fit.poles_]
    nominal = fit.model_.poles[k]
    rng = np.random.default_rng(1)
    drawn = np.array([perturb_poles(fit, rng).poles[k] for _ in range(20)])
    zeta = -drawn.real / np.abs(drawn)
    assert zeta[:, 0] == pytest.approx(-nominal[0].real / abs(nominal[0]), rel=1e-9)
    assert np.std(np.abs(drawn[:, 0])) > 0
    assert np.all(np.std(zeta[:, 1:], axis=0) > 0)


def test_band_of_a_mass_on_a_measured_rod_is_built_from_its_components():
    """nominal -+ band_half_width(sigma, truncation, tail): sigma from the residue draws'
    and the pole draws' rms changes, the tail's estimate the change at half the extent, the
    truncation's the largest over the cut bands (each taken with its own fraction's
    noise)."""
    from scipy.stats import norm

    from impactpred.truncation import FIGURES, band_resolution, identified_model
    from impactpred.uncertainty import band_half_width, front_allowance, front_jump

    fit = _measured_fixed_rod()
    models = [LumpedMass(1.0), identified_model(fit)]
    band = uncertainty_band(models, [None, fit], _solve_mass_on, n_draws=3, level=0.9,
                            fractions=(0.6, 0.8))
    labels = [label for label, _ in band.variants]
    assert labels[:3] == ["tail to 8x the band top", "body2 band 60%", "body2 band 80%"]
    assert labels[3:] == ["draw 1", "draw 2", "draw 3", "pole draw 1", "pole draw 2",
                          "pole draw 3"] and band.level == 0.9
    variants = dict(band.variants)
    z = norm.ppf(1 - 0.1 / 8)
    assert z == pytest.approx(2.2414, abs=1e-4)
    for k in FIGURES:
        assert band.tail[k] == abs(band.nominal[k] - variants["tail to 8x the band top"][k])
        changes = [variants[f"draw {d}"][k] - band.nominal[k] for d in (1, 2, 3)]
        assert band.spread[k] == pytest.approx(np.sqrt(np.mean(np.square(changes))),
                                               rel=1e-12)
        changes = [variants[f"pole draw {d}"][k] - band.nominal[k] for d in (1, 2, 3)]
        assert band.pole_spread[k] == pytest.approx(np.sqrt(np.mean(np.square(changes))),
                                                    rel=1e-12)
        cuts = [truncation_error(band.nominal, variants[f"body2 band {p}%"], p / 100)[k]
                for p in (60, 80)]
        assert band.truncation[k] == max(cuts)
        half = max(band_half_width(band.spread[k], t, band.tail[k], figure=k, fraction=p / 100,
                                   pole_spread=band.pole_spread[k])
                   for t, p in zip(cuts, (60, 80)))
        # the peak reaches further down by the wave front's overshoot (a rigid contact)
        assert band.low[k] == pytest.approx(band.nominal[k] - half - band.front[k], rel=1e-12)
        assert band.high[k] == pytest.approx(band.nominal[k] + half, rel=1e-12)
        assert band.truncation[k] >= 0 and band.spread[k] > 0 and band.pole_spread[k] > 0
    resolution = band_resolution([None, fit])
    jump = front_jump(_solve_mass_on(*models), resolution)
    assert band.front == {**dict.fromkeys(FIGURES, 0.0),
                          "peak_force": front_allowance(jump, 1)}
    assert 1.7 < jump < 2.3         # undamped, the force jumps by 2 N at t = 2 s (zeta 1e-3)
    # a lower level, a narrower band; the same variants (same seed)
    narrow = uncertainty_band(models, [None, fit], _solve_mass_on, n_draws=3, level=0.5,
                              fractions=(0.6, 0.8))
    for k in FIGURES:
        assert narrow.high[k] - narrow.low[k] < band.high[k] - band.low[k]
    # the band holds the measured (damped, zeta = 1e-3) structure's own answer: its first
    # 10 modes and residual, continued (zeta alone takes ~0.5 % off the continuum's e)
    from impactpred.truncation import continue_above_band, impact_figures

    truth = lightly_damped(Rod(1.0, 1.0, support="fixed"), 20, 1e-3).truncate(10, residual=True)
    own = impact_figures(_solve_mass_on(LumpedMass(1.0), continue_above_band(
        truth, fit.report_["band_hz"][1])), resolution=band_resolution([None, fit]))
    for k in FIGURES:
        assert band.low[k] <= own[k] <= band.high[k]
    assert band_resolution([None, fit]) == pytest.approx(0.5 / fit.report_["band_hz"][1])


def test_the_overshoot_at_a_wave_front_is_within_the_peaks_allowance():
    """A mass M = m on a fixed rod: the exact force (method.md, closed form) jumps from
    exp(-2) to 2 + exp(-2) N when the wave reflected at the support returns (t = 2 T).
    The rod's first 10 modes (+ residual) continued, as an identified model is, overshoot
    the jump by less than FRONT_OVERSHOOT of it; the jump read off the prediction is the
    exact one to within that overshoot; and the allowance makes the peak's interval hold
    the exact peak. A smooth peak (a mass on a spring) has no jump to speak of."""
    from data_synth.reference_impacts import mass_on_fixed_rod
    from impactpred.truncation import continue_above_band, impact_figures
    from impactpred.uncertainty import FRONT_OVERSHOOT, front_allowance, front_jump

    exact = mass_on_fixed_rod(1.0, 1.0, 1.0, 1.0, np.linspace(0.0, 8.0, 80001))
    exact_peak = 2.0 + np.exp(-2.0)
    assert np.max(exact.force) == pytest.approx(exact_peak, rel=1e-4)
    rod = lightly_damped(Rod(1.0, 1.0, support="fixed"), 20, 1e-4).truncate(10, residual=True)
    continued = _solve_mass_on(LumpedMass(1.0), continue_above_band(rod, 5.0))
    resolution = 0.5 / 5.0
    peak = impact_figures(continued, resolution=resolution)["peak_force"]
    jump = front_jump(continued, resolution)
    overshoot = peak - exact_peak
    assert 0.0 < overshoot < FRONT_OVERSHOOT * 2.0          # above the exact, within it
    assert 2.0 <= jump <= 2.0 + 3 * overshoot     # + the crest above and the trough below
    assert peak - front_allowance(jump, 1) < exact_peak < peak
    assert front_allowance(jump, 2) == 2 * front_allowance(jump, 1)
    assert front_allowance(-1.0, 1) == 0.0
    # two masses through a spring: a half-sine of force (2.2 s long), smooth at its crest
    from impactpred import Body, solve_impact
    from impactpred.contact import LinearSpring

    smooth = solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(LumpedMass(1.0)),
                          contact=LinearSpring(1.0), t_end=4.0, dt=1e-3)
    top = impact_figures(smooth)["peak_force"]
    assert front_jump(smooth, 0.05) < 0.005 * top       # 1 - cos(0.05 sqrt(2)) = 0.0025
    assert front_jump(smooth, 0.0) == 0.0


def test_a_compliant_contact_gets_no_front_allowance():
    """A spring-dashpot or Hertz law keeps the force continuous: no jump to overshoot."""
    from impactpred.contact import LinearSpring
    from impactpred.truncation import identified_model

    fit = _measured_fixed_rod()
    models = [LumpedMass(1.0), identified_model(fit)]
    nominal = _solve_mass_on(*models)
    kwargs = dict(n_draws=0, nominal=nominal, cheap_variants=True)
    rigid = uncertainty_band(models, [None, fit], _solve_mass_on, **kwargs)
    spring = uncertainty_band(models, [None, fit], _solve_mass_on,
                              contact=LinearSpring(1e7), **kwargs)
    assert rigid.front["peak_force"] > 0.0
    assert all(v == 0.0 for v in spring.front.values())
    assert spring.high == rigid.high
    assert spring.low["peak_force"] == pytest.approx(
        rigid.low["peak_force"] + rigid.front["peak_force"], rel=1e-12)
    with pytest.raises(TypeError, match="contact"):
        uncertainty_band(models, [None, fit], _solve_mass_on, contact="rigid", **kwargs)


def test_cheap_variants_are_measured_against_the_nominal_at_half_the_tail():
    """With cheap_variants the draws and the cut band are solved with the tail to half its
    extent and compared with the nominal solved the same way (the tail's estimate): no
    draws, the spread is 0 and the band's width is the truncation and tail estimates."""
    from impactpred.truncation import identified_model
    from impactpred.uncertainty import TAIL_FACTOR, TRUNCATION_FACTOR

    fit = _measured_fixed_rod()
    models = [LumpedMass(1.0), identified_model(fit)]
    band = uncertainty_band(models, [None, fit], _solve_mass_on, n_draws=0,
                            cheap_variants=True)
    assert [label for label, _ in band.variants] == ["tail to 8x the band top",
                                                     "body2 band 80%"]
    # a refit cache: one re-identification for two bands, the same band
    refits = {}
    first = uncertainty_band(models, [None, fit], _solve_mass_on, n_draws=0,
                             cheap_variants=True, refits=refits)
    again = uncertainty_band(models, [None, fit], _solve_mass_on, n_draws=0,
                             cheap_variants=True, refits=refits)
    assert list(refits) == [(id(fit), 0.8)]
    assert first.low == again.low == band.low and first.high == band.high
    assert all(v == 0.0 for v in band.spread.values())
    for k in band.truncation:         # no spread: nothing of the truncation is noise
        assert band.high[k] - band.nominal[k] == pytest.approx(
            TRUNCATION_FACTOR * band.truncation[k] + TAIL_FACTOR * band.tail[k], rel=1e-12)


def test_the_band_counts_its_variants_on_a_bar_when_asked(capsys):
    """``progress=True``: a bar on stderr counts the re-identification and the solves
    (the tail's, the cut band's); False (the default) and "auto" on a short band print
    nothing, and the band is the same."""
    from impactpred.truncation import identified_model

    fit = _measured_fixed_rod()
    models = [LumpedMass(1.0), identified_model(fit)]
    kw = dict(n_draws=0, cheap_variants=True)
    quiet = uncertainty_band(models, [None, fit], _solve_mass_on, **kw)
    assert capsys.readouterr().err == ""
    auto = uncertainty_band(models, [None, fit], _solve_mass_on, progress="auto", **kw)
    assert capsys.readouterr().err == ""
    shown = uncertainty_band(models, [None, fit], _solve_mass_on, progress=True, **kw)
    assert "band variants: 3 solve" in capsys.readouterr().err
    assert quiet.low == auto.low == shown.low and quiet.high == shown.high


def test_half_width_takes_the_noise_out_of_the_truncation_estimate():
    """sqrt((z k sigma)^2 + (a max(T - sigma sqrt(f/(1-f)), 0))^2) + b tail: a cut band's
    change within the re-identification's own noise adds nothing to the spread; beyond it,
    the rest adds in quadrature; every figure's tail takes the same factor (the peak's
    wave front has its own, one-sided allowance)."""
    from scipy.stats import norm

    from impactpred.uncertainty import (
        SPREAD_FACTOR,
        TAIL_FACTOR,
        TRUNCATION_FACTOR,
        band_half_width,
    )

    z = norm.ppf(1 - 0.1 / 8)
    spread = z * SPREAD_FACTOR * 0.3
    # at 80 % the noise in a truncation estimate is 2 sigma: 0.5 of it is all noise
    assert band_half_width(0.3, 0.5, 0.0, figure="impulse") == pytest.approx(spread)
    assert band_half_width(0.3, 0.6, 0.0, figure="impulse") == pytest.approx(spread)
    assert band_half_width(0.3, 1.6, 0.0, figure="impulse") == pytest.approx(
        np.hypot(spread, TRUNCATION_FACTOR * 1.0))
    # at 60 % it is sigma sqrt(1.5)
    assert band_half_width(0.3, 1.6, 0.0, figure="impulse", fraction=0.6) == pytest.approx(
        np.hypot(spread, TRUNCATION_FACTOR * (1.6 - 0.3 * np.sqrt(1.5))))
    # without draws the estimate is taken whole; the tail is added
    assert band_half_width(0.0, 1.0, 0.2, figure="restitution") == pytest.approx(
        TRUNCATION_FACTOR + TAIL_FACTOR * 0.2)
    assert band_half_width(0.0, 1.0, 0.2, figure="peak_force") == pytest.approx(
        TRUNCATION_FACTOR + TAIL_FACTOR * 0.2)
    # a lower level, a narrower interval
    assert band_half_width(0.3, 1.6, 0.1, figure="impulse", level=0.5) < band_half_width(
        0.3, 1.6, 0.1, figure="impulse")
    for kwargs, match in (({"figure": "force"}, "figure"),
                          ({"figure": "impulse", "fraction": 1.0}, "fraction"),
                          ({"figure": "impulse", "level": 0.0}, "level")):
        with pytest.raises(ValueError, match=match):
            band_half_width(0.3, 1.0, 0.0, **kwargs)


@pytest.mark.parametrize("kwargs, match", [
    ({"extend": float("nan")}, "extend"), ({"extend": -3.0}, "extend"),
    ({"n_draws": -2}, "n_draws"), ({"n_draws": 2.5}, "n_draws"),
    ({"n_top": 0}, "n_top"), ({"fractions": (0.6, 1.2)}, "fractions"),
    ({"level": 1.0}, "level"), ({"level": 0.0}, "level"),
])
def test_band_options_are_checked(kwargs, match):
    with pytest.raises(ValueError, match=match):
        uncertainty_band([LumpedMass(1.0), LumpedMass(1.0)], [None, None], None, **kwargs)


@pytest.mark.parametrize("error", [ValueError, RuntimeError])
def test_draws_that_cannot_be_solved_are_said_not_dropped_silently(error):
    """Every draw refused by the solver (a RuntimeError: the exact solver's undecidable
    grazing contact): the band says so (its spread parts are then 0)."""
    from impactpred.truncation import identified_model

    fit = _measured_fixed_rod()
    models = [LumpedMass(1.0), identified_model(fit)]
    nominal = _solve_mass_on(*models)

    def refuse(m1, m2):
        raise error("refused for the test")

    with pytest.warns(RuntimeWarning) as caught:
        band = uncertainty_band(models, [None, fit], refuse, n_draws=3, nominal=nominal)
    messages = [str(w.message) for w in caught]
    for what in ("residue", "pole"):
        assert any(m.startswith(f"3 of 3 {what} draws could not be solved (first: "
                                f"{error.__name__}: refused for the test)") and
                   m.endswith(f": it has no {what} spread part") for m in messages), messages
    assert all(v == 0.0 for v in band.spread.values())
    assert all(v == 0.0 for v in band.pole_spread.values())


def test_a_variant_whose_outcome_changes_in_kind_is_said():
    """A variant that ends with the bodies still in contact (no restitution: left out of
    the spread) is listed in the band and its table, and warned about, and the
    restitution's interval is all it can be, [-1, 1] (from the other variants alone it
    had been a narrow one: a ball on a beam's [0.25, 0.36] for an exact 0.059); a band
    whose variants agree with their references lists none."""
    from impactpred import Body, solve_impact
    from impactpred.truncation import identified_model
    from impactpred.uncertainty import outcome_change

    fit = _measured_fixed_rod()
    models = [LumpedMass(1.0), identified_model(fit)]      # continued, as the band's
    nominal = _solve_mass_on(*models)
    calls = []

    def solve(m1, m2):           # the third solve ends before the bodies part
        calls.append(1)
        t_end = 0.05 if len(calls) == 3 else 8.0
        return solve_impact(Body(m1, velocity=1.0), Body(m2), t_end=t_end, method="laplace")

    with pytest.warns(UserWarning, match="the outcome changes in kind in 1 of") as said:
        band = uncertainty_band(models, [None, fit], solve, n_draws=2, nominal=nominal)
    assert any("its interval is all it can be: restitution [-1, 1]" in str(w.message)
               for w in said)
    assert (band.low["restitution"], band.high["restitution"]) == (-1.0, 1.0)
    assert band.low["impulse"] < nominal.impulse < band.high["impulse"]
    assert len(band.outcome_changes) == 1
    assert band.outcome_changes[0].endswith("restitution undefined")
    assert nominal.restitution is not None
    assert "the outcome changes in kind in 1 of" in band.table()
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)
        agreeing = uncertainty_band(models, [None, fit], _solve_mass_on, n_draws=2,
                                    nominal=nominal)
    assert agreeing.outcome_changes == () and "outcome" not in agreeing.table()
    figs = {"contact_duration": 1.0, "peak_force": 2.0, "impulse": 3.0, "restitution": 0.5,
            "n_contacts": 1}
    assert outcome_change(figs, dict(figs)) is None
    assert outcome_change(figs, dict(figs, n_contacts=2)) == "2 contacts instead of 1"
    assert outcome_change(dict(figs, restitution=None), figs) == "restitution defined"


def test_a_band_for_one_continued_and_one_lumped_body(tmp_path):
    """A free rod's file (continued above its band) striking a spring-mass's (its band
    shows no compliance above it: not continued): the band's variants continue each body
    as the nominal prediction did; asking the spring-mass's for a continuation raised
    "no compliance above it" from inside the band. Still in contact at ``t_end``, the
    restitution is undefined and the table says so."""
    from data_synth import SpringMass, synthetic_frf
    from impactpred import predict
    from modalid import write_frf

    spring_mass = lightly_damped(SpringMass(1.773799480628025, 920663.2681301013), 1, 3e-4)
    write_frf(tmp_path / "spring_mass.csv",
              synthetic_frf(spring_mass, np.linspace(297.7 / 2000, 297.7, 2000),
                            quantity="accelerance", noise=0.01, seed=1))
    rod = lightly_damped(Rod(1.0, 0.01), 300, 1e-3)
    write_frf(tmp_path / "rod.csv", synthetic_frf(rod, np.linspace(0.25, 500.0, 2000),
                                                  quantity="accelerance", noise=0.01, seed=2))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pred = predict(tmp_path / "rod.csv", tmp_path / "spring_mass.csv", velocity1=1.0,
                       contact="hertz:1e9", t_end=0.02, uncertainty=True)
    assert pred.continuation[0].startswith("on")
    assert "no compliance above" in pred.continuation[1]
    band = pred.uncertainty
    assert band.nominal["restitution"] is None
    assert band.low["peak_force"] <= band.nominal["peak_force"] <= band.high["peak_force"]
    assert "restitution" in band.table() and " -" in band.table()


def test_a_band_stays_within_what_each_figure_can_be():
    """A spread wider than the figure (a chattering run's peak force, from four draws:
    random_predictions.py seed 1 case 10) had given a peak force's interval down to
    -272 N; the interval is cut to what the figure can be."""
    from impactpred.uncertainty import _physical_interval

    assert _physical_interval("peak_force", -272.0, 900.0) == (0.0, 900.0)
    assert _physical_interval("contact_duration", 0.01, 0.02) == (0.01, 0.02)
    assert _physical_interval("impulse", -1e-3, 2.0) == (0.0, 2.0)
    assert _physical_interval("restitution", -1.4, 1.2) == (-1.0, 1.0)
    assert _physical_interval("restitution", 0.5, 0.7) == (0.5, 0.7)


def test_a_saved_fit_has_no_data_to_re_identify():
    """A SavedFit keeps the model and report, not the data: the band (and its cut-band
    re-identification) refuses it before any solve, naming where it came from."""
    from impactpred.uncertainty import refit_on_cut_band
    from modalid import FitReport, ModalModel, SavedFit

    model = ModalModel.from_modes([2 * np.pi * 10.0], [0.02], [1.0])
    saved = SavedFit(model_=model, report_=FitReport({"band_hz": (1.0, 40.0), "n_modes": 1,
                                                      "verdict": "ok"}), source="body.csv")
    message = r"^a SavedFit \(body\.csv\) holds no data to re-identify on a cut band"
    with pytest.raises(ValueError, match=message):
        refit_on_cut_band(saved, 0.8)
    with pytest.raises(ValueError, match=message):
        uncertainty_band([LumpedMass(1.0), model], [None, saved], None)


def test_a_common_pole_fit_of_several_frfs_has_no_band_and_says_so():
    """A ModalFit of an FRFSet (predict takes it as a body, its driving row the model) has
    no single FRF's parameters to draw: refused by name before any solve (the draws had
    failed inside ModalModel: "residues must be 1-D")."""
    from impactpred.uncertainty import check_band_bodies
    from modalid import FRFSet

    rod = Rod(1.0, 1.0, support="fixed")
    freq = np.linspace(0.01, 3.25, 650)
    rows = [rod.frf(2 * np.pi * freq)]
    rows.append(0.5 * rows[0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit().fit(FRFSet(freq, np.array(rows)))
    with pytest.raises(ValueError, match=r"^body 2 \(an FRFSet fit\) is a common-pole fit "
                                         r"of several FRFs: .*driving point's FRF alone"):
        check_band_bodies(["mass:1", "an FRFSet fit"], [None, fit])
    with pytest.raises(ValueError, match=r"^a common-pole fit of several FRFs"):
        uncertainty_band([LumpedMass(1.0), LumpedMass(1.0)], [None, fit], None)
