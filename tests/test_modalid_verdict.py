"""The driving-point decision and the quality verdict (modalid._verdict) on modal tables
whose answer is known, and on the fits of exact FRFs."""

import warnings

import numpy as np
import pandas as pd
import pytest

from data_synth import CantileverBeam
from modalid import ModalModel
from modalid import FRFData
from modalid._verdict import (damping_resolved, driving_point_decision, mass_line_share,
                              missed_resonances, quality_verdict)


def modes_of(poles, residues):
    return ModalModel(poles=np.asarray(poles, complex), residues=np.asarray(residues)).modes


POLES = [-1 + 100j, -2 + 300j, -3 + 500j]


def test_one_sign_is_a_driving_point_mixed_signs_a_transfer():
    driving = modes_of(POLES, [-0.01j, -0.02j, -0.015j])       # Im r < 0: m > 0
    assert driving_point_decision(driving, 0.0)[0] is True
    # a negative mass line (the modes' strength sum 1/m is 29 1/kg), unless it is weaker
    # than a tenth of them (a windowed hammer FRF's slight low-end misfit)
    assert driving_point_decision(driving, -5.0)[0] is False
    ok, why = driving_point_decision(driving, -1.0)
    assert ok is True and "a negative mass line of -1 1/kg, under a tenth" in why
    mixed = modes_of(POLES, [-0.01j, 0.02j, -0.015j])
    ok, why = driving_point_decision(mixed, 0.0)
    assert ok is False and "transfer" in why
    reversed_sign = modes_of(POLES, [0.01j, 0.02j, 0.015j])
    ok, why = driving_point_decision(reversed_sign, 0.0)
    assert ok is False and "sign reversed" in why
    # a weak mode of the other sign (under 10 % of the strength 1/|m|) is noise
    weak = modes_of(POLES, [-0.01j, -0.02j, 0.0005j])
    assert driving_point_decision(weak, 0.0)[0] is True
    assert driving_point_decision(modes_of([], []), 0.0)[0] is True


def test_a_slight_negative_mass_line_must_also_be_slight_in_the_data():
    """A negative mass line under a tenth of the modes' strength is not counted only where
    it makes under a quarter of the band's lowest lines (below half the first mode): a
    transfer FRF's rigid term is what those lines show."""
    driving = modes_of(POLES, [-0.01j, -0.02j, -0.015j])       # strength 29 1/kg
    freq = np.arange(1.0, 8.0, 0.25)                           # below 100 rad/s / 2
    omega = 2 * np.pi * freq
    for inverse_mass, share in ((-1.0, 1.0), (-1.0, 0.1)):
        # data of which the mass line makes the share: the rest a static flexibility
        data = FRFData(freq, -inverse_mass / omega ** 2 / share + 0j)
        assert mass_line_share(data, inverse_mass, driving) == pytest.approx(share)
        ok, why = driving_point_decision(driving, inverse_mass, data=data)
        if share == 1.0:
            assert ok is False and "making 100 % of the data below the modes" in why
        else:
            assert ok is True and "under a tenth" in why
    # no line below the modes: the strength alone decides
    high = FRFData(np.arange(40.0, 60.0), np.ones(20, complex))
    assert np.isnan(mass_line_share(high, -1.0, driving))
    assert driving_point_decision(driving, -1.0, data=high)[0] is True


def test_damping_is_resolved_only_when_the_lines_resolve_it():
    modes = modes_of([-1e-3 + 100j, -5 + 300j], [-0.01j, -0.02j])
    # half-power bandwidths 2 zeta f: 3.2e-4 Hz and 1.6 Hz; lines 0.5 Hz apart
    assert damping_resolved(modes, 0.5).tolist() == [False, True]
    assert damping_resolved(modes, 1e-4).tolist() == [True, True]


def verdict(modes, **kw):
    settings = dict(band_hz=(1.0, 100.0), driving_point=True, nrmse=0.01, relative_error=0.01,
                    relative_noise=0.01, rigid_body=False, finite=True)
    settings.update(kw)
    return quality_verdict(modes, **settings)


def test_the_verdict_names_what_is_wrong():
    good = modes_of(POLES, [-0.01j, -0.02j, -0.015j])
    assert verdict(good) == ("ok", [])
    state, why = verdict(good, nrmse=1.2, relative_error=0.9)
    assert state == "failed" and "zero model" in why[0]
    state, why = verdict(good, finite=False)
    assert state == "failed" and "not finite" in why[0]
    state, why = verdict(good, nrmse=0.3, relative_error=0.2)
    assert state == "suspect" and "modes may be missing" in why[0]
    # noisy data: an error the scatter explains is no fault
    assert verdict(good, nrmse=0.3, relative_error=0.2, relative_noise=0.1)[0] == "ok"
    mixed = modes_of(POLES, [-0.01j, 0.02j, -0.015j])
    state, why = verdict(mixed)
    assert state == "suspect" and "negative modal mass at a driving point" in why[0]
    assert verdict(mixed, driving_point=False)[0] == "ok"
    bound = modes_of([-1e-8 + 100j], [-0.01j])
    state, why = verdict(bound)
    assert state == "suspect" and "lower bound" in why[0]
    state, why = verdict(modes_of([], []), nrmse=0.9, relative_error=0.9)
    assert state == "failed" and "no resonance in the band" in why
    outside = modes_of([-1 + 2000j], [-0.01j])
    assert "outside the band" in verdict(outside)[1][0]


def test_an_error_far_above_the_noise_is_suspect_even_when_most_lines_fit():
    """A sharp peak missed: most lines fit to the noise (median error 1 %) but the FRF
    error is 31 %, 31 times the data's 1 % scatter (a draft segmentation's fit of 50
    random modes at zeta 1e-2 on 2401 lines, benchmarks/many_modes.py: 13 extra modes,
    and the verdict was "ok")."""
    good = modes_of(POLES, [-0.01j, -0.02j, -0.015j])
    state, why = verdict(good, nrmse=0.31, relative_error=0.01, relative_noise=0.01)
    assert state == "suspect" and "31 times the data's scatter" in why[0]
    assert "peaks are missed" in why[0]
    assert verdict(good, nrmse=0.15, relative_error=0.01)[0] == "ok"          # under 20 %
    assert verdict(good, nrmse=0.31, relative_error=0.05, relative_noise=0.05)[0] == "ok"
    assert verdict(good, nrmse=0.31, relative_error=0.01, relative_noise=np.nan)[0] == "ok"
    state, why = verdict(good, nrmse=0.31, relative_error=0.01, relative_noise=0.0)
    assert state == "suspect" and "far above the data's scatter" in why[0]   # exact data
    # a set: the gate judges the row given (its own error against its own scatter)
    assert verdict(good, nrmse=0.31, relative_error=0.05, relative_noise=0.05)[0] == "ok"
    state, why = verdict(good, nrmse=0.31, relative_error=0.05, relative_noise=0.05,
                         miss=(0.25, 0.01))
    assert state == "suspect" and "25 times the data's scatter" in why[0]


def test_exact_fits_are_ok_and_a_noise_fit_fails():
    from modalid import FRFData, ModalFit

    truth = CantileverBeam(1.0, 1.0).modal_model(12, damping_ratio=0.01, residual=True)
    freq = np.linspace(0.02, 40.0, 2000)
    fit = ModalFit().fit(FRFData(freq, truth.frf(2 * np.pi * freq)))
    r = fit.report_
    assert r["verdict"] == "ok" and r["driving_point"] is True and r["weighting"] == "relative"
    assert bool(np.all(r["modes"]["damping_resolved"]))
    rng = np.random.default_rng(0)
    noise = rng.normal(size=freq.size) + 1j * rng.normal(size=freq.size)
    import warnings

    with warnings.catch_warnings(record=True):
        warnings.simplefilter("always")
        fit = ModalFit().fit(FRFData(freq, 1e-3 * noise))
    assert fit.report_["verdict"] in ("failed", "suspect")
    assert isinstance(fit.report_["verdict_reasons"], list) and fit.report_["verdict_reasons"]
    assert isinstance(pd.DataFrame(fit.report_["modes"]), pd.DataFrame)


def test_a_fit_of_an_undamped_models_frf_says_why_it_is_suspect():
    """An exact undamped FRF is real at every line: no line resolves its infinitely sharp
    resonances. Weighted 1/|H| the fit misses most (a fixed rod's 10 modes on 1001 lines:
    15 modes, negative masses among them, 6 of the 10 resonances missed, "suspect"; with
    two missed-mode passes none, "failed"); refitted by the data's own scatter
    (``weighting="auto"``) it finds all ten, exactly, their damping at the refinement's
    bound: "suspect", and the verdict says why and what to do."""
    import warnings

    from data_synth import Rod, lightly_damped, synthetic_frf
    from modalid import ModalFit
    from modalid._verdict import UNDAMPED_REASON, undamped_lines

    freq = np.linspace(1.0, 5000.0, 1001)
    exact = synthetic_frf(Rod(1.0, 1e-3, support="fixed"), freq)
    assert undamped_lines(exact.values)
    assert undamped_lines(1j * exact.values)                       # mobility
    assert not undamped_lines(exact.values * np.exp(0.01j))
    mixed = exact.values.copy()
    mixed[::2] *= 1j                                   # some lines real, some imaginary
    assert not undamped_lines(mixed)
    assert not undamped_lines(np.zeros(5)) and not undamped_lines(np.array([np.nan, 1.0]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit().fit(exact)
    assert fit.report_["verdict"] == "suspect" and fit.report_["weighting"] == "noise"
    assert fit.report_["verdict_reasons"][-1] == UNDAMPED_REASON
    # the 1/|H| fit it replaced is at the mercy of rounding on these lines (no line
    # resolves a resonance): no passive driving point, or failed outright (session #35,
    # the model's sum evaluated exactly at the poles' lines)
    reason = fit.report_["weighting_reason"]
    assert reason.startswith("the fit weighted 1/|H| ") and (
        "was no passive driving point" in reason or "1/|H| failed" in reason)
    np.testing.assert_allclose(fit.report_["modes"]["frequency_hz"],
                               250.0 + 500.0 * np.arange(10), rtol=1e-6)
    np.testing.assert_allclose(fit.report_["modes"]["modal_mass"], 0.5, rtol=1e-3)
    relative = ModalFit(weighting="relative")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        relative.fit(exact)
    # weighted 1/|H|: most missed, "suspect", or none found, "failed" (the docstring)
    assert relative.report_["verdict"] in ("suspect", "failed")
    assert len(relative.report_["missed_resonances_hz"]) >= 5
    assert relative.report_["verdict_reasons"][-1] == UNDAMPED_REASON
    damped = synthetic_frf(lightly_damped(Rod(1.0, 1e-3, support="fixed"), 20, 1e-3), freq)
    assert not undamped_lines(damped.values)
    assert ModalFit().fit(damped).report_["verdict"] == "ok"


def test_a_resonance_the_model_misses_is_named_and_makes_the_fit_suspect():
    """Three exact modes of damping 1e-4 on 2000 lines, 1 % noise: a model without the
    middle mode misses its peak (at its line and both neighbours, far above the noise);
    the whole model misses none; a lone spike of 20 times its line, added to the data, is
    no resonance missed (no skirt)."""
    poles = np.array([-1e-4 * 2 * np.pi * f + 2j * np.pi * f for f in (10.0, 23.0, 41.0)])
    whole = ModalModel(poles=poles, residues=np.array([-0.01j, -0.012j, -0.008j]))
    freq_hz = np.linspace(1.0, 50.0, 2000)
    omega = 2 * np.pi * freq_hz
    rng = np.random.default_rng(3)
    exact = whole.frf(omega)
    data = exact * (1 + 0.01 * (rng.standard_normal(omega.size)
                                + 1j * rng.standard_normal(omega.size)) / np.sqrt(2))
    without = ModalModel(poles=poles[[0, 2]], residues=whole.residues[[0, 2]])
    missed = missed_resonances(freq_hz, data, without.frf(omega))
    assert missed.size == 1 and abs(missed[0] - 23.0) < 2 * (freq_hz[1] - freq_hz[0])
    assert missed_resonances(freq_hz, data, exact).size == 0
    spiked = data.copy()
    spiked[700] *= 20.0
    assert missed_resonances(freq_hz, spiked, exact).size == 0
    modes = whole.modes
    verdict, reasons = quality_verdict(modes, band_hz=(1.0, 50.0), driving_point=True,
                                       nrmse=0.01, relative_error=0.01, relative_noise=0.01,
                                       rigid_body=False, finite=True, missed_hz=missed)
    assert verdict == "suspect" and len(reasons) == 1
    assert reasons[0].startswith(f"the data's resonance at {missed[0]:.6g} Hz is missed")


def test_a_wrong_quantity_is_named_as_the_decision_reads_it():
    """A three-mode receptance given as a mobility or an accelerance read as a
    receptance, and as an accelerance read as a mobility: every modal mass negative, and
    the reason names those readings (a mobility read as a receptance flips them too)."""
    import warnings

    from modalid import FRFData, ModalFit

    m = ModalModel.from_modes(2 * np.pi * np.array([100.0, 250.0, 600.0]),
                              [0.02, 0.01, 0.01], [1.0, 2.0, 0.5])
    f = np.linspace(10.0, 1000.0, 2000)
    w = 2 * np.pi * f
    for factor, read in ((1j * w, "receptance"), (-w ** 2, "receptance"),
                         (-w ** 2, "mobility")):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fit = ModalFit().fit(FRFData(f, m.frf(w) * factor, quantity=read))
        assert fit.report_["driving_point"] is False
        assert ("a mobility or an accelerance read as a receptance, an accelerance read as "
                "a mobility" in fit.report_["driving_point_reason"])


def test_the_verdict_says_where_a_large_error_sits():
    """An FRF error of 100 % with a median line error under 1 %: junk lines at the band's
    bottom (a receptance's noise lines blown up, 1e6 times the band's level) were said to
    be "the lines near the peaks". :func:`error_lines` finds the fewest lines that carry
    half the error and whether they sit at the modes' peaks; the reason names them."""
    from modalid._verdict import error_lines, quality_verdict

    freq = np.linspace(0.25, 1000.0, 4000)
    poles = np.array([-2 * np.pi * 2.0 + 2j * np.pi * 200.0])     # 200 Hz, 2 Hz half-width
    junk = np.zeros(freq.size, complex)
    junk[0], junk[1:] = 5.0, 1e-4
    where = error_lines(freq, junk, poles)
    assert where.startswith("half of it on 1 line at 0.25 Hz, where the data stand far off")
    at_peak = np.zeros(freq.size, complex)
    near = np.abs(freq - 200.0) < 3.0
    at_peak[near] = 1.0
    where_peak = error_lines(freq, at_peak, poles)
    assert where_peak == "the lines near the peaks are missed"
    at_peak[np.abs(freq - 600.0) < 3.0] = 2.0              # more of it, off the mode
    assert error_lines(freq, at_peak, poles).startswith("half of it on")
    modes = ModalModel(poles=poles, residues=[-0.5j / abs(poles[0])]).modes
    kw = dict(band_hz=(0.25, 1000.0), driving_point=True, nrmse=1.0 - 1e-3,
              relative_error=0.008, relative_noise=0.003, rigid_body=False, finite=True)
    _, reasons = quality_verdict(modes, **kw, error_lines=where)
    assert "half of it on 1 line at 0.25 Hz, where the data stand far off the model" \
        in reasons[0]
    _, reasons = quality_verdict(modes, **kw, error_lines=where_peak)
    assert "the lines near the peaks are missed" in reasons[0]


def test_missed_low_end_finds_a_run_of_missed_lowest_lines():
    """:func:`missed_low_end` on data of one everywhere: the lowest 40 of 1000 lines at a
    thousandth in the model are a missed low end, (first line, 40th); 5 of 1000 (under a
    hundredth of the band), a run starting at the fourth line, or every line within
    half, are not."""
    from modalid._verdict import missed_low_end

    freq = np.arange(1.0, 1001.0)
    data = np.ones(1000, complex) * np.exp(1j * 0.01 * freq)   # smooth: scatter ~ 0
    for missed, expected in ((slice(0, 40), (1.0, 40.0)), (slice(0, 5), None),
                             (slice(3, 60), None)):
        model = data.copy()
        model[missed] *= 1e-3
        assert missed_low_end(freq, data, model) == expected
    assert missed_low_end(freq, data, 0.6 * data) is None


def test_an_aliased_hammer_test_is_no_silent_passive_driving_point():
    """A 1 kg free rod (modes every 50 Hz) on a 2 Hz suspension, hammer-tested at 4096 Hz
    without an anti-alias filter (the records' top folded onto the lowest lines), fitted
    on 0.5-1500 Hz: the passive fit, with neither a mass line nor a mode below the band,
    missed 0.5-65 Hz by 10-10 000 times and was a driving point, "ok"; a mass striking it
    came out 56 % off in impulse, silently. Its missed low end makes it suspect, and the
    unconstrained fit, which follows those lines, is no passive driving point."""
    from data_synth import Rod, lightly_damped, synthetic_hammer_test
    from modalid import ModalFit, ModalModel, frf_from_hammer

    rod = lightly_damped(Rod(1.0, 10e-3, support="free"), 40, 0.005)
    bounce = ModalModel.from_modes([2 * np.pi * 2.0], [0.05], [1.0])
    body = ModalModel(poles=np.r_[bounce.poles, rod.poles],
                      residues=np.r_[bounce.residues, rod.residues])
    test = synthetic_hammer_test(body, 4096.0, 2.0, n_hits=5, pulse_width=1e-3, noise=0.01,
                                 noise_reference="rms", seed=1, anti_alias=False)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        est = frf_from_hammer(test.force, test.response, 4096.0,
                              response_type="acceleration", exponential_decay=np.log(100) / 2)
        passive = ModalFit(freq_range=(None, 1500.0), passive=True,
                           **est.fit_options()).fit(est.frf)
        fit = ModalFit(freq_range=(None, 1500.0), **est.fit_options()).fit(est.frf)
    low = passive.report_["missed_low_end_hz"]
    assert passive.report_["verdict"] == "suspect" and low[0] == 0.5 and low[1] > 30.0
    assert "the band's lowest lines" in passive.report_["verdict_reasons"][0]
    assert fit.report_["driving_point"] is False
