"""ModalFit against exact truths: lightly damped rods and a cantilever, with known noise.

Truth: ``model.modal_model(8 + 10, damping_ratio=0.01, residual=True)`` (the band's 8
modes, 10 more above the band, the exact static flexibility of the rest); 4000 lines up to
halfway between modes 8 and 9; noise proportional to the FRF, ``H (1 + eta e)`` with ``e``
circular complex Gaussian of unit variance, fixed seeds. Tolerances scale with the noise
``eta`` and are checked against the fit's own standard deviations too.
"""

import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from sklearn.base import clone

from data_synth import CantileverBeam, Rod, synthetic_frf
from modalid import FRFData, ModalModel
from modalid.fit import ModalFit, ModalFitWarning

DATA = Path(__file__).parent / "data"

N_BAND, ZETA = 8, 0.01
STRUCTURES = {
    "beam": lambda: CantileverBeam(1.0, 1.0),
    "fixed rod": lambda: Rod(1.0, 1.0, support="fixed"),
    "free rod": lambda: Rod(1.0, 1.0, support="free"),
}


def truth_of(name):
    return STRUCTURES[name]().modal_model(N_BAND + 10, damping_ratio=ZETA, residual=True)


def frf_case(name, noise=0.0, seed=0, n_lines=4000):
    """(truth, noisy FRFData, noise-free values)."""
    truth = truth_of(name)
    wn = truth.modes["omega_n"].to_numpy()
    fmax = 0.5 * (wn[N_BAND - 1] + wn[N_BAND]) / (2 * np.pi)
    freq = np.linspace(fmax / n_lines, fmax, n_lines)
    exact = truth.frf(2 * np.pi * freq)
    rng = np.random.default_rng(seed)
    e = (rng.normal(size=n_lines) + 1j * rng.normal(size=n_lines)) / np.sqrt(2)
    return truth, FRFData(freq, exact * (1 + noise * e)), exact


_FITS = {}


def fitted(name, noise, seed=0, **settings):
    """Fits are cached: several tests read the same one."""
    key = (name, noise, seed, tuple(sorted(settings.items())))
    if key not in _FITS:
        truth, data, exact = frf_case(name, noise, seed)
        _FITS[key] = (truth, data, exact, ModalFit(**settings).fit(data))
    return _FITS[key]


def paired(truth, modes, n=N_BAND):
    """The identified modes nearest to the first ``n`` true ones; each exactly once."""
    true = truth.modes.iloc[:n].reset_index(drop=True)
    index = [int(np.argmin(np.abs(modes["omega_n"].to_numpy() - w))) for w in true["omega_n"]]
    assert len(set(index)) == n, f"modes missed or merged: {modes['frequency_hz'].tolist()}"
    return true, modes.iloc[index].reset_index(drop=True)


def relative_errors(true, ident):
    df = np.abs(ident["omega_n"].to_numpy() / true["omega_n"].to_numpy() - 1)
    dz = np.abs(ident["damping_ratio"].to_numpy() / true["damping_ratio"].to_numpy() - 1)
    dr = np.abs(ident["residue"].to_numpy() / true["residue"].to_numpy() - 1)
    return df, dz, dr


# ------------------------------------------------------------------------- clean data
@pytest.mark.parametrize("name", list(STRUCTURES))
def test_clean_frf_reaches_the_targets(name):
    truth, data, exact, fit = fitted(name, 0.0)
    assert fit.report_["n_modes"] == N_BAND and fit.poles_.size == N_BAND
    df, dz, dr = relative_errors(*paired(truth, fit.report_["modes"]))
    assert df.max() < 1e-5 and dz.max() < 1e-3 and dr.max() < 1e-3
    assert fit.report_["converged"]
    assert fit.model_.is_stable() and fit.model_.is_passive()
    np.testing.assert_allclose(fit.predict(data.omega), exact, rtol=0,
                               atol=1e-4 * np.abs(exact).max())
    if truth.inverse_mass:
        assert fit.report_["rigid_body"]
        assert fit.report_["rigid_mass"] == pytest.approx(1 / truth.inverse_mass, rel=1e-4)
    else:
        assert not fit.report_["rigid_body"] and fit.model_.inverse_mass == 0


# ------------------------------------------------------------------------- noisy data
@pytest.mark.parametrize("noise", [0.01, 0.05])
@pytest.mark.parametrize("name", list(STRUCTURES))
@pytest.mark.parametrize("seed", [0, 3])
def test_noisy_frf_within_the_noise(name, noise, seed):
    truth, data, exact, fit = fitted(name, noise, seed)
    report = fit.report_
    assert report["converged"] and report["n_modes"] == N_BAND
    true, ident = paired(truth, report["modes"])
    df, dz, dr = relative_errors(true, ident)
    # tolerances proportional to the noise (5 %: 0.125 %, 7.5 %, 1.5 %) ...
    assert df.max() < 0.025 * noise
    assert dz.max() < 1.5 * noise
    assert dr.max() < 0.3 * noise
    # ... and each error within 4.5 of the fit's own standard deviations
    assert np.all(np.abs(ident["frequency_hz"] - true["frequency_hz"])
                  < 4.5 * ident["frequency_hz_std"])
    assert np.all(np.abs(ident["damping_ratio"] - true["damping_ratio"])
                  < 4.5 * ident["damping_ratio_std"])
    assert np.all(np.abs(ident["residue"] - true["residue"]) < 4.5 * ident["residue_std"])
    # no spurious, unstable or negative-mass mode; the model is passive
    assert np.all(ident["modal_mass"] > 0) and fit.model_.is_passive()
    assert fit.model_.is_stable()
    # the FRF: the residual against the data is the noise, against the truth far below it
    fitted_frf = fit.predict(data.omega)
    relative = np.sqrt(np.mean(np.abs(fitted_frf / exact - 1) ** 2))
    assert relative < 0.25 * noise
    if truth.inverse_mass:
        assert report["rigid_mass"] == pytest.approx(1 / truth.inverse_mass, rel=0.2 * noise)
    else:
        assert not report["rigid_body"]


@pytest.mark.parametrize("name", list(STRUCTURES))
def test_issue_targets_at_five_percent_noise_over_five_seeds(name):
    """0.05 % / 5 % / 1 % (frequency, damping, residue), rigid mass 1 %, FRF NRMSE 2 %.

    The cantilever's first mode has one line per half-power band: the noise alone puts
    its frequency and damping errors at 4e-4 and 4 % (one standard deviation, also what a
    fit started from the true values reaches), and its peak lines dominate the NRMSE; the
    targets are asserted for its other modes and at four standard deviations for it.
    """
    for seed in range(5):
        truth, data, exact, fit = fitted(name, 0.05, seed)
        assert fit.report_["n_modes"] == N_BAND and fit.model_.is_passive()
        true, ident = paired(truth, fit.report_["modes"])
        df, dz, dr = relative_errors(true, ident)
        first = 1 if name == "beam" else 0
        assert df[first:].max() < 5e-4 and dz[first:].max() < 0.05 and dr.max() < 0.01
        assert df[0] < 4 * ident["frequency_hz_std"][0] / ident["frequency_hz"][0]
        assert dz[0] < 4 * ident["damping_ratio_std"][0] / ident["damping_ratio"][0]
        nrmse = np.linalg.norm(fit.predict(data.omega) - exact) / np.linalg.norm(exact)
        assert nrmse < (0.07 if name == "beam" else 0.02)
        if truth.inverse_mass:
            assert fit.report_["rigid_mass"] == pytest.approx(1.0, rel=0.01)


def test_report_gives_the_high_frequency_behaviour():
    truth, data, _, fit = fitted("free rod", 0.01)
    report, model = fit.report_, fit.model_
    masses = model.modes["modal_mass"].to_numpy()
    assert report["effective_mass"] == pytest.approx(
        1 / (np.sum(1 / masses) + model.inverse_mass), rel=1e-12)
    assert report["residual_flexibility"] == model.flexibility >= 0
    # the in-band modes and the rigid body of a free rod: M_eff = 1/(1/M + sum 2/m)
    assert report["effective_mass_physical"] == pytest.approx(1 / (1 + 2 * N_BAND), rel=0.01)
    assert report["upper_residual_modes"] >= 1 and not report["lower_residual_mode"]


# ------------------------------------------------------------------- other estimators
@pytest.mark.parametrize("name", list(STRUCTURES))
def test_era_from_a_clean_impulse_response(name):
    truth = truth_of(name)
    fs = 2.5 * truth.modes["omega_n"].to_numpy()[-1] / (2 * np.pi)
    t = np.arange(8000) / fs
    fit = ModalFit(method="era").fit((t, truth.impulse_response(t)))
    assert fit.model_.n_modes == N_BAND + 10 and fit.report_["converged"]
    df, dz, dr = relative_errors(*paired(truth, fit.model_.modes, n=N_BAND + 10))
    assert df.max() < 1e-8 and dz.max() < 1e-6 and dr.max() < 1e-6
    assert fit.model_.inverse_mass == pytest.approx(truth.inverse_mass, abs=1e-8)


@pytest.mark.parametrize("name,noise", [("fixed rod", 0.05), ("beam", 0.01)])
def test_vector_fitting_agrees_with_lscf(name, noise):
    truth, data, _, lscf = fitted(name, noise)
    vf = ModalFit(method="vf").fit(data)
    assert vf.report_["n_modes"] == N_BAND
    np.testing.assert_allclose(vf.poles_, lscf.poles_, rtol=1e-5)
    df, dz, dr = relative_errors(*paired(truth, vf.report_["modes"]))
    assert df.max() < 0.025 * noise and dz.max() < 1.5 * noise and dr.max() < 0.3 * noise


# ----------------------------------------------------------------------- overrides
def test_n_modes_as_a_count_or_frequencies_gives_the_automatic_result():
    truth, data, _, auto = fitted("fixed rod", 0.01)
    by_count = ModalFit(n_modes=N_BAND).fit(data)
    f_true = truth.modes["frequency_hz"].to_numpy()[:N_BAND]
    by_freq = ModalFit(n_modes=f_true * (1 + 0.01 * (-1) ** np.arange(N_BAND))).fit(data)
    for fit in (by_count, by_freq):
        np.testing.assert_allclose(fit.poles_, auto.poles_, rtol=1e-6)


def test_n_modes_frequencies_on_a_narrower_band():
    truth, data, _ = frf_case("fixed rod", 0.01)
    fit = ModalFit(n_modes=[0.25, 0.75, 1.25], freq_range=(0.0, 1.5)).fit(data)
    assert fit.report_["n_modes"] == 3
    df, dz, dr = relative_errors(*paired(truth, fit.report_["modes"], n=3))
    assert df.max() < 3e-4 and dz.max() < 0.02 and dr.max() < 0.005


def test_band_cut_above_the_first_modes_uses_the_lower_residual():
    truth, data, _ = frf_case("fixed rod", 0.01)
    fit = ModalFit(freq_range=(1.0, 4.0)).fit(data)
    report = fit.report_
    assert report["lower_residual_mode"] and not report["rigid_body"]
    assert report["n_modes"] == 6
    true = truth.modes.iloc[2:N_BAND].reset_index(drop=True)
    ident = report["modes"]
    df, dz, dr = relative_errors(true, ident)
    assert df.max() < 3e-4 and dz.max() < 0.02 and dr.max() < 0.01


def test_mobility_input_gives_the_receptance_fit():
    _, data, _, fit = fitted("fixed rod", 0.01)
    mobility = FRFData(data.freq_hz, 2j * np.pi * data.freq_hz * data.values,
                       quantity="mobility")
    np.testing.assert_allclose(ModalFit().fit(mobility).poles_, fit.poles_, rtol=1e-7)


def test_noise_weighting_estimates_the_noise_from_the_data():
    truth, data, _ = frf_case("fixed rod", 0.01)
    fit = ModalFit(weighting="noise").fit(data)
    assert fit.report_["n_modes"] == N_BAND
    df, dz, dr = relative_errors(*paired(truth, fit.report_["modes"]))
    assert df.max() < 2.5e-4 and dz.max() < 0.015 and dr.max() < 0.003


def test_negative_modal_masses_warn_when_passive_is_forced():
    truth, data, _ = frf_case("fixed rod", 0.01)
    reversed_sign = FRFData(data.freq_hz, -data.values)
    with pytest.warns(ModalFitWarning) as record:
        fit = ModalFit(passive=True).fit(reversed_sign)
    assert any("negative modal mass" in str(w.message) for w in record)
    assert fit.report_["n_modes"] == 0 and fit.report_["verdict"] == "failed"
    for fit in (ModalFit().fit(reversed_sign), ModalFit(passive=False).fit(reversed_sign)):
        assert fit.report_["n_modes"] == N_BAND
        true, ident = paired(truth, fit.report_["modes"])
        np.testing.assert_allclose(ident["modal_mass"], -0.5, rtol=0.01)
    # the default decides from the data: every modal mass negative, the sign reversed
    fit = ModalFit().fit(reversed_sign)
    assert fit.report_["driving_point"] is False
    assert "sign reversed" in fit.report_["driving_point_reason"]
    true, ident = paired(truth, fit.report_["modes"])
    np.testing.assert_allclose(ident["modal_mass"], -0.5, rtol=0.01)
    np.testing.assert_allclose(ident["residue"], -true["residue"], rtol=0.005)


def test_measured_accelerance_of_a_transfer_frf():
    """vibration_toolbox's case1.mat: one sharp resonance near 212.1 Hz (two lines per
    half-power band) with a negative modal mass, over a noise floor."""
    from pathlib import Path

    from scipy.io import loadmat

    mat = loadmat(Path(__file__).parent / "data" / "case1.mat")
    freq = np.ravel(mat["Freq_domain"]).astype(float)
    data = FRFData(freq, np.ravel(mat["Hf_chan_2"]), quantity="accelerance")
    band = data.band((20.0, 400.0))
    fit = ModalFit(passive=False, weighting="noise").fit(band)
    modes = fit.report_["modes"]
    main = modes.iloc[int(np.argmin(np.abs(modes["frequency_hz"] - 212.1)))]
    assert main["frequency_hz"] == pytest.approx(212.1, abs=0.2)
    assert 2e-4 < main["damping_ratio"] < 3e-3 and main["modal_mass"] < 0
    assert fit.score(band) > 0.95


# ------------------------------------------------------------------------ bad input
def test_nan_is_refused_by_frfdata():
    _, data, _ = frf_case("fixed rod")
    values = np.array(data.values)
    values[10] = np.nan
    with pytest.raises(ValueError, match="finite"):
        FRFData(data.freq_hz, values)


def test_empty_band_is_an_error():
    _, data, _ = frf_case("fixed rod")
    with pytest.raises(ValueError, match="empty band"):
        ModalFit(freq_range=(10.0, 20.0)).fit(data)


def test_band_without_resonance_warns_and_reports_it():
    _, data, exact = frf_case("fixed rod", 0.01)
    with pytest.warns(ModalFitWarning, match="no resonance"):
        fit = ModalFit(freq_range=(0.0, 0.2)).fit(data)
    assert fit.report_["n_modes"] == 0 and fit.poles_.size == 0
    assert any("no resonance" in note for note in fit.report_["notes"])
    band = data.freq_hz <= 0.2
    np.testing.assert_allclose(fit.predict(data.omega[band]), exact[band], rtol=0.01)


def test_noise_free_data_without_resonance_fit_exactly():
    """A lumped mass's exact accelerance (a flat 1/m) and a constant receptance: the fit
    is exact (zero residual), which divided the residual's median by itself (0 / 0) and
    the far pseudo-mode's gain by a zero variance (a ZeroDivisionError)."""
    from data_synth import LumpedMass
    from data_synth.measure import synthetic_frf

    mass = synthetic_frf(LumpedMass(2.0), np.linspace(1.0, 100.0, 200), quantity="accelerance")
    flat = FRFData(np.arange(1.0, 11.0), np.full(10, 1e-6 + 0j))
    for data, inverse_mass, flexibility in ((mass, 0.5, 0.0), (flat, 0.0, 1e-6)):
        with warnings.catch_warnings():
            warnings.simplefilter("error", RuntimeWarning)
            with pytest.warns(ModalFitWarning, match="no resonance"):
                fit = ModalFit().fit(data)
        assert fit.report_["verdict"] == "ok" and fit.report_["n_modes"] == 0
        assert fit.model_.inverse_mass == pytest.approx(inverse_mass, rel=1e-12, abs=1e-15)
        assert fit.model_.flexibility == pytest.approx(flexibility, rel=1e-12, abs=1e-15)


def test_non_convergence_warns_and_reports_it(monkeypatch):
    import modalid._frf_pipeline as fit_module

    original = fit_module.refine_varpro

    def one_step(*args, **kwargs):
        # the refinement stops after one step, and the probe of whether more steps would
        # move the poles (10 steps, no std) is made to see them move by 1 %
        probe = kwargs.get("max_iter") == 10 and kwargs.get("with_std") is False
        kwargs["max_iter"] = 1
        poles, x, info = original(*args, **kwargs)
        return (poles * 1.01 if probe else poles), x, info

    monkeypatch.setattr(fit_module, "refine_varpro", one_step)
    _, data, _ = frf_case("beam", 0.05)
    with pytest.warns(ModalFitWarning, match="did not converge"):
        fit = ModalFit().fit(data)
    assert not fit.report_["converged"]
    assert "maximum number of iterations" in fit.report_["message"]


def test_a_result_that_more_steps_would_not_move_is_converged():
    """pyuff point 2 reaches the step limit; ten more steps move no pole by a tenth of
    its standard deviation: no convergence warning, the message says why."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fit = ModalFit().fit(_real("meas_point_2.txt"))
    assert fit.report_["converged"]
    assert not any("did not converge" in str(w.message) for w in caught)
    message = fit.report_["message"]
    assert (message.startswith("settled:") or "converged" in message
            or message == "no further decrease of the cost")


@pytest.mark.parametrize("settings, error", [
    (dict(method="lsce"), ValueError), (dict(weighting="log"), ValueError),
    (dict(rigid_body="yes"), ValueError), (dict(residuals=("middle",)), ValueError),
    (dict(n_modes=0), ValueError), (dict(n_modes=[-1.0]), ValueError),
    (dict(n_modes=2.5), TypeError),
    (dict(residuals=None), TypeError), (dict(residuals="upper"), TypeError),
])
def test_bad_settings_raise(settings, error):
    _, data, _ = frf_case("fixed rod", n_lines=200)
    with pytest.raises(error):
        ModalFit(**settings).fit(data)


def test_bad_data_raise():
    _, data, _ = frf_case("fixed rod", n_lines=200)
    with pytest.raises(TypeError, match="FRFData"):
        ModalFit().fit((data.freq_hz, data.values))
    with pytest.raises(TypeError, match="impulse response"):
        ModalFit(method="era").fit(data)
    t = np.r_[0.0, np.cumsum(np.linspace(1e-3, 2e-3, 99))]
    with pytest.raises(ValueError, match="uniformly spaced"):
        ModalFit(method="era").fit((t, np.sin(t)))
    with pytest.raises(ValueError, match="not fitted"):
        ModalFit().predict([1.0])
    # all zeros: was "Array must not contain infs or NaNs" (from a zero-scaled solve);
    # 1e300: overflow warnings deep in the fit
    zero = FRFData(data.freq_hz, np.zeros(len(data)), quantity="accelerance")
    with pytest.raises(ValueError, match=r"^the FRF \(accelerance, 200 lines\) is 0 at every "
                                         r"line: nothing to identify$"):
        ModalFit().fit(zero)
    for scale in (1e300, 1e-300):
        huge = FRFData(data.freq_hz, data.values * scale / np.max(np.abs(data.values)),
                       quantity=data.quantity)
        with pytest.raises(ValueError, match=r"largest value is 1e[+-]300 .*check the file's "
                                             r"units or scaling$"):
            ModalFit().fit(huge)


def test_a_band_of_too_few_lines_is_refused_naming_it():
    """A user's band of 2 lines crashed deep in numpy (IndexError); of 3, it returned an
    "ok" fit of a mode and two pseudo-modes through three points. A given band needs 4
    (with 5, :func:`test_a_band_of_a_few_lines_is_fitted_not_crashed`)."""
    _, data, _ = frf_case("fixed rod", n_lines=200)
    f = data.freq_hz
    for n in (2, 3):
        with pytest.raises(ValueError, match=rf"freq_range .* holds {n} lines of the data; "
                                             "a fit needs at least 4"):
            ModalFit(freq_range=(f[50], f[50 + n - 1])).fit(data)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit(freq_range=(f[50], f[53])).fit(data)
    assert fit.data_.freq_hz.size == 4
    with pytest.raises(TypeError, match="data must be an FRFData or an FRFSet, got NoneType"):
        fit.score(None)
    with pytest.raises(TypeError, match="data must be an FRFData or an FRFSet, got str"):
        fit.plot_fit(data="x")


# --------------------------------------------------------------- estimator protocol
def test_scikit_learn_conventions_and_plots():
    import matplotlib

    matplotlib.use("Agg")
    _, data, exact, fit = fitted("fixed rod", 0.01)
    estimator = ModalFit(n_modes=3, freq_range=(0.0, 1.5))
    assert clone(estimator).get_params() == estimator.get_params()
    assert estimator.fit(data) is estimator
    assert estimator.score(data) > 0.99 and fit.score(data) > 0.99
    ax = fit.plot_stabilization()
    assert ax.get_xlabel() == "frequency (Hz)"
    assert len(fit.plot_fit().get_lines()) == 2
    assert fit.plot_fit(data=data.select(slice(0, 100))).get_lines()
    assert len(fit.stabilization_) > 0 and fit.clusters_["selected"].sum() == N_BAND


@pytest.mark.filterwarnings("ignore::UserWarning")
@pytest.mark.parametrize("point", [1, 2, 3])
def test_measured_free_free_beam_gives_its_six_modes(point):
    """pyuff's measured accelerances (tests/data): six resonances between 50 and 1000 Hz."""
    from modalid.io import read_complex_lines

    data = read_complex_lines(DATA / f"meas_point_{point}.txt", freq_hz=np.arange(1001.0),
                              quantity="accelerance").band((20, 1000))
    fit = ModalFit(passive=False, weighting="noise").fit(data)
    np.testing.assert_allclose(np.sort(fit.report_["modes"]["frequency_hz"].to_numpy()),
                               [52, 142, 279, 460, 687, 959], atol=1.0)
    assert fit.score(data) > 0.99


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_noisy_analyzer_export_case2():
    """vibration_toolbox's case2 (coherence ~0.3): its published mode at 192.59 Hz."""
    from modalid.io import read_frf

    data = read_frf(DATA / "case2.mat", quantity="accelerance").band((156.25, 312.5))
    fit = ModalFit(passive=False, weighting="noise").fit(data)
    freqs = fit.report_["modes"]["frequency_hz"].to_numpy()
    assert np.min(np.abs(freqs - 192.59)) < 0.5


def test_noise_candidates_of_case2_are_refused_by_the_wider_candidates_gate():
    """case2 on 100-300 Hz, no options: no persistent LSCF candidate is supported, and the
    less persistent ones (``WIDER_SHARE``) explain only 55 % of the misfit (ratio 0.45,
    above ``WIDER_MISFIT``): they are refused, and the one resonance is found by the
    missed-mode search as before. Taken, they had kept a 120 Hz mode (FRF error 73 ->
    96 %)."""
    from modalid.io import read_frf

    data = read_frf(DATA / "case2.mat", quantity="accelerance")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit(freq_range=(100, 300)).fit(data)
    freqs = fit.report_["modes"]["frequency_hz"].to_numpy(float)
    assert freqs.size == 1 and abs(freqs[0] - 192.59) < 0.3


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_sharp_modes_the_persistent_candidates_half_miss_are_found_under_noise(seed):
    """Thirteen modes of damping 5e-5 to 2e-4 on 5 Hz lines (half-power bandwidths 1/77
    to 1/5 of a line), 1 % noise: the persistent LSCF candidates hold 5-9 of them and leave
    a third to nine tenths of the misfit; the wider ones (``WIDER_SHARE``) explain it
    290-1150 times better and are taken. Before, the missed-mode search added the rest
    one at a time and its refinements merged 3971 and 4132 Hz into one mode at 4158 Hz or
    lost the lowest or the top one: 12 of 13, "suspect", on every seed. The passive pass
    takes them too (its selection thinned of negative masses, judged by the misfit of the
    poles kept): refused, its fit failed and the FRF was called no driving point."""
    from data_synth import synthetic_frf

    freq = np.array([273.2, 303.2, 431.2, 899.3, 1061.3, 1361.3, 1993.3, 3227.4, 3340.2,
                     3971.1, 4131.9, 4420.1, 4614.1])
    rng = np.random.default_rng(7)
    truth = ModalModel.from_modes(2 * np.pi * freq, 1e-4 * 2.0 ** rng.uniform(-1, 1, 13),
                                  rng.uniform(0.5, 5.0, 13))
    data = synthetic_frf(truth, np.arange(1.0, 4800.0, 5.0), noise=0.01, seed=seed)
    assert _assert_finds_every_mode(data, freq, rtol=1e-4)["driving_point"] is True


def _assert_finds_every_mode(data, true_hz, rtol):
    """``ModalFit()`` on ``data``: verdict ok, every frequency of ``true_hz`` (sorted)
    found within ``rtol`` and no other mode; returns the fit's report."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit().fit(data)
    found = np.sort(fit.report_["modes"]["frequency_hz"].to_numpy(float))
    assert fit.report_["verdict"] == "ok" and found.size == true_hz.size
    assert np.allclose(found, true_hz, rtol=rtol)
    return fit.report_


@pytest.mark.parametrize("n_lines", [2401, 4001])
def test_modes_far_narrower_than_their_lines_are_found_under_noise(n_lines):
    """Fifty modes of damping about 1e-4 on 5-8 Hz lines (half-power bandwidths of 1/140
    of a line to 1.5 lines) with 1 % noise, fitted by segments. In the first segment no
    persistent candidate was supported (the rest missing, none lowers the relative
    misfit), and the missed-mode search's one-at-a-time refinements lost every mode below
    4.4 kHz: 39 of 50, FRF error 100 %, "failed". The wider candidates
    (``WIDER_SHARE``) find all of them."""
    from data_synth import random_modal_model, synthetic_frf

    truth = random_modal_model(50, (200.0, 19800.0), 1e-4, seed=7)  # many_modes.py's
    true_hz = np.sort(truth.modes["frequency_hz"].to_numpy(float))
    data = synthetic_frf(truth, np.linspace(1.0, 20000.0, n_lines), noise=0.01, seed=1)
    _assert_finds_every_mode(data, true_hz, rtol=3e-4)


def test_the_upper_pseudo_mode_does_not_start_on_the_held_one():
    """A cantilever's receptance, 11 modes in band and the 12th 18 % above its top, 3 %
    noise (case 16 of ``benchmarks/random_predictions.py --seed 1``): the free upper
    pseudo-mode's best start was twice the band top, the held far pseudo-mode's modulus;
    the passive fit then held both at zero modal mass, dropped them as idle, and bent
    the top modes' masses to stand for the modes above (75 Hz: 1.13 kg for 1.21; FRF
    error 3.0 % instead of 2.1 %; an impact's restitution 0.351 for the exact 0.412). The
    upper pseudo-mode no longer starts there."""
    from data_synth import lightly_damped, synthetic_frf

    beam = CantileverBeam(4.842354847908811, 2.3073630074983287)
    truth = lightly_damped(beam, 300, 0.004943069779360769)
    top = 76.50824676251273
    data = synthetic_frf(truth, np.linspace(top / 2000, top, 2000), noise=0.03, seed=16)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit().fit(data)
    r = fit.report_
    assert r["upper_residual_modes"] >= 1 and r["modes"].shape[0] == 11
    masses = r["modes"]["modal_mass"].to_numpy(float)
    np.testing.assert_allclose(masses, truth.modes["modal_mass"].to_numpy(float)[:11],
                               rtol=0.02)


def _transfer_accelerance():
    """A transfer accelerance: a negative mass line (accelerance -> -1 at low frequency),
    close modes at 100 and 103 Hz of opposite sign, a mode at 200 Hz."""
    wn = 2 * np.pi * np.array([100.0, 103.0, 200.0])
    truth = ModalModel.from_modes(wn, [0.005, 0.005, 0.01], [2.0, -3.0, 1.5])
    freq = np.arange(20.0, 400.0, 0.25)
    values = truth.frf(2 * np.pi * freq, quantity="accelerance") - 1.0
    return FRFData(freq, values, quantity="accelerance"), wn / (2 * np.pi)


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_transfer_with_negative_mass_line_and_data_quantity_nrmse():
    data, freqs = _transfer_accelerance()
    fit = ModalFit(passive=False, freq_range=(30, 380)).fit(data)
    assert fit.report_["lower_residual_mode"]
    found = np.abs(fit.poles_) / (2 * np.pi)
    assert np.all(np.min(np.abs(found[:, None] - freqs), axis=0) < 1e-4 * freqs)
    assert fit.report_["data_quantity"] == "accelerance"
    assert fit.report_["frf_nrmse_data"] < 1e-3


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_frequency_list_keeps_one_pole_per_frequency():
    data, freqs = _transfer_accelerance()
    fit = ModalFit(passive=False, freq_range=(30, 380), n_modes=[99.5, 103.2, 201.0],
                   refine=True).fit(data)
    assert fit.report_["n_modes"] == 3
    np.testing.assert_allclose(np.abs(fit.poles_) / (2 * np.pi), freqs, rtol=1e-4)


# ------------------------------------------------------------ given weights, pole bound
def test_given_weights_fit_clean_data_exactly():
    """Weights change which lines count, not the answer: on exact data any positive
    weights give the truth (here weights that favour the upper half of the band)."""
    truth, data, _ = frf_case("fixed rod")
    w = np.linspace(0.2, 5.0, data.freq_hz.size)
    fit = ModalFit(weights=w).fit(data)
    df, dz, dr = relative_errors(*paired(truth, fit.report_["modes"]))
    assert df.max() < 1e-5 and dz.max() < 1e-3 and dr.max() < 1e-3


def _by_frequency(fit):
    """The fit's physical poles and residues, by frequency."""
    modes = fit.report_["modes"]
    order = np.argsort(modes["omega_n"].to_numpy())
    return (fit.poles_[np.argsort(np.abs(fit.poles_))],
            modes["residue"].to_numpy()[order])


def test_fit_weights_zeroing_a_band_equal_the_fit_without_its_lines():
    """``fit(data, weights=w)``: a line of weight 0 is out of the fit, so zeroing the lines
    of 1.6-2.1 Hz (mode 4 at 1.75 Hz among them) gives the fit of the data without them
    (equal weights elsewhere: ``weighting="uniform"``), to within the refinement's
    convergence (5e-7; noise 2 %: the band's lines, put back, move the poles by 3e-3 and
    the residues by 2e-2). The weights' scale does not matter, and the estimator's
    ``weights`` setting is the same route."""
    _, data, _ = frf_case("fixed rod", noise=0.02, seed=3, n_lines=1200)
    hole = (data.freq_hz > 1.6) & (data.freq_hz < 2.1)
    settings = dict(n_modes=8, freq_range=(0, np.inf), passive=True, rigid_body=False)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModalFitWarning)
        without = ModalFit(weighting="uniform", **settings).fit(data.select(~hole))
        zeroed = ModalFit(**settings).fit(data, weights=np.where(hole, 0.0, 1.0))
        scaled = ModalFit(**settings).fit(data, weights=np.where(hole, 0.0, 3.0))
        setting = ModalFit(weights=np.where(hole, 0.0, 1.0), **settings).fit(data)
        every_line = ModalFit(**settings).fit(data, weights=np.ones(data.freq_hz.size))
    p0, r0 = _by_frequency(without)
    for fit in (zeroed, scaled, setting):
        p, r = _by_frequency(fit)
        np.testing.assert_allclose(p, p0, rtol=1e-5)
        np.testing.assert_allclose(r, r0, rtol=1e-4)
    p, r = _by_frequency(every_line)          # the test can tell the lines apart
    assert np.max(np.abs(p / p0 - 1)) > 1e-3 and np.max(np.abs(r / r0 - 1)) > 1e-2
    # the fit's weights are the data's: not a setting, not carried by a clone, but kept
    # on the lines fitted (data_) for a re-fit
    assert zeroed.get_params()["weights"] is None
    assert "_line_weights" not in clone(zeroed).__dict__
    np.testing.assert_array_equal(zeroed.weights_, np.where(hole, 0.0, 1.0))
    assert zeroed.data_.freq_hz.size == data.freq_hz.size and without.weights_ is None


@pytest.mark.parametrize("weights, match", [
    (np.ones(3), "weights must be 4000 values"),
    (-np.ones(4000), "weights must be >= 0, got -1.0 at line 0"),
    (np.r_[np.ones(3999), np.nan], "weights must be finite"),
    (np.zeros(4000), "weights must not be all 0"),
    (np.r_[np.ones(100), np.zeros(3900)], "all 0 on the band fitted"),
    ([[1.0, 2.0]], "weights must be 1-D"),
])
def test_bad_fit_weights_raise_naming_the_value(weights, match):
    _, data, _ = frf_case("fixed rod")
    fit = ModalFit(freq_range=(1.0, np.inf))
    with pytest.raises(ValueError, match=match):
        fit.fit(data, weights=weights)


def test_fit_weights_apply_to_one_frf_and_are_given_once():
    from modalid import FRFSet

    truth, data, _ = frf_case("fixed rod")
    w = np.ones(data.freq_hz.size)
    with pytest.raises(ValueError, match="given twice"):
        ModalFit(weights=w).fit(data, weights=w)
    frf_set = FRFSet.from_frfs([data, data], driving_point=0)
    with pytest.raises(ValueError, match="FRFData fit only"):
        ModalFit().fit(frf_set, weights=w)
    t = np.linspace(0.0, 20.0, 2001)
    with pytest.raises(ValueError, match="'lscf' or 'vf' only"):
        ModalFit(method="era").fit((t, truth.impulse_response(t)), weights=w)


def test_pole_bound_holds_for_every_refined_pole():
    # e.g. an exponential window added 2x the lightest mode's decay to every pole: the
    # refined poles must keep at least that much, so they stay stable once it is removed.
    # Here the bound is active (the true lightest poles decay slower than it).
    truth, data, _ = frf_case("fixed rod")
    lightest = float(np.min(-truth.poles.real))
    bound = -2.0 * lightest
    free = ModalFit(method="vf").fit(data)
    assert np.any(free.model_.poles.real > bound)          # without it, it is crossed
    fit = ModalFit(method="vf", max_real=bound).fit(data)
    assert np.all(fit.model_.poles.real <= bound * (1 - 1e-12))
    # the modes are still all found, at their frequencies
    true, ident = paired(truth, fit.report_["modes"])
    df = np.abs(ident["omega_n"].to_numpy() / true["omega_n"].to_numpy() - 1)
    assert df.max() < 1e-3


@pytest.mark.parametrize("settings, match", [
    (dict(weights=np.ones(3)), "weights must be"),
    (dict(weights=-np.ones(4000)), "weights must be"),
    (dict(max_real=0.0), "max_real must be negative"),
    (dict(max_real=1.0), "max_real must be negative"),
    (dict(method="era", max_real=-1.0), "lscf' or 'vf' only"),
])
def test_bad_weights_and_pole_bound_raise(settings, match):
    _, data, _ = frf_case("fixed rod")
    with pytest.raises(ValueError, match=match):
        ModalFit(**settings).fit(data)


def test_a_resonance_at_the_lowest_lines_is_not_taken_for_a_mass_line():
    """A cantilever whose first mode sits at line 3.6 of a windowed hammer FRF (the
    synthetic benchmark's rod-cantilever at 20 modes): the pole estimator misses it, and the
    lowest lines' falling magnitude once read as a rigid body's mass line (mass 2.5 kg on a
    grounded beam). Their real part changes sign at the resonance, which a mass line's
    never does: the mode is placed there and identified, and no rigid body is fitted."""
    from data_synth import lightly_damped, synthetic_hammer_test
    from modalid import frf_from_hammer

    truth = lightly_damped(CantileverBeam(10.0, 4.0), 30, 1e-4)
    wn = truth.modes["omega_n"].to_numpy()
    top = 0.5 * (wn[19] + wn[20]) / (2 * np.pi)
    duration, fs = 4000 / top, 5 * top
    test = synthetic_hammer_test(truth, fs, duration, n_hits=5, pulse_width=0.5 / top,
                                 noise=0.05, response="velocity", seed=0, anti_alias=True,
                                 noise_reference="rms")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        est = frf_from_hammer(test.force, test.response, fs, response_type="velocity",
                              exponential_decay=np.log(100) / duration)
        fit = ModalFit(weighting="noise", **est.fit_options()).fit(
            est.frf.band((1 / duration, top)))
    f1 = truth.modes["frequency_hz"].iloc[0]
    assert f1 * duration < 4                        # the first mode at the lowest lines
    assert fit.model_.inverse_mass == 0.0 and not fit.report_["rigid_body"]
    found = fit.model_.modes["frequency_hz"].to_numpy()
    assert np.min(np.abs(found / f1 - 1)) < 0.02
    assert any("below the first pole" in note for note in fit.report_["notes"])


def test_dense_missed_modes_find_what_the_pole_estimator_left_out():
    """A fixed rod with 16 modes in band and a stabilization diagram too small to hold them
    (max_order=12): "dense" adds every mode the information criterion supports: all 16,
    none spurious, at the noise's accuracy. "strict" adds a missed mode only when it
    halves the cost; with six additions per pass it kept 13, with a budget that
    grows with the band's peaks (16 here: eight per pass) it finds all 16 as well."""
    n_band = 16
    truth = Rod(1.0, 1.0, support="fixed").modal_model(n_band + 10, damping_ratio=0.005,
                                                       residual=True)
    wn = truth.modes["omega_n"].to_numpy()
    fmax = 0.5 * (wn[n_band - 1] + wn[n_band]) / (2 * np.pi)
    freq = np.linspace(fmax / 4000, fmax, 4000)
    rng = np.random.default_rng(0)
    noise = (rng.normal(size=freq.size) + 1j * rng.normal(size=freq.size)) / np.sqrt(2)
    data = FRFData(freq, truth.frf(2 * np.pi * freq) * (1 + 0.01 * noise))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        strict = ModalFit(max_order=12).fit(data)
        dense = ModalFit(max_order=12, missed_modes="dense").fit(data)
    for fit in (strict, dense):
        assert fit.report_["n_modes"] == n_band
        found = fit.report_["modes"]["omega_n"].to_numpy()
        np.testing.assert_allclose(np.sort(found), wn[:n_band], rtol=2e-4)
        assert any("missed" in note for note in fit.report_["notes"])
    with pytest.raises(ValueError, match="missed_modes"):
        ModalFit(missed_modes="all").fit(data)


def _windowed_cantilever(line, end, noise, seed):
    """A cantilever's mobility as an exponentially windowed, truncated hammer FRF (exact:
    modalid._window), its first mode at ``line`` lines of the record, the window ending at
    ``end``; 20 modes in band, zeta = 1e-4."""
    from modalid._window import windowed_receptance

    truth = CantileverBeam(1.0, 1.0).modal_model(30, damping_ratio=1e-4, residual=True)
    wn = truth.modes["omega_n"].to_numpy()
    length = line * 2 * np.pi / wn[0]
    top = 0.5 * (wn[19] + wn[20]) / (2 * np.pi)
    freq = np.arange(1, int(top * length) + 1) / length
    sigma = -np.log(end) / length
    values = windowed_receptance(truth, 2 * np.pi * freq, sigma, length, quantity="mobility")
    rng = np.random.default_rng(seed)
    values = values * (1 + noise * (rng.normal(size=freq.size)
                                    + 1j * rng.normal(size=freq.size)) / np.sqrt(2))
    data = FRFData(freq, values * 2j * np.pi * freq, quantity="mobility")
    return truth, data, {"window_decay_rate": sigma, "record_length": length}


@pytest.mark.parametrize("line, end, noise", [(2.3, 0.01, 0.05), (3.6, 1e-3, 0.0),
                                              (4.4, 1e-4, 0.05), (6.0, 1e-4, 0.0)])
def test_a_windowed_first_mode_at_the_lowest_lines_is_found(line, end, noise):
    """Windows ending at 1 % to 0.01 %: no rigid body on the grounded beam, its first three
    modes found (within 2 %). The significance test judges the structure's damping, not
    the windowed pole's (up to 0.3 and more at the lowest lines)."""
    truth, data, options = _windowed_cantilever(line, end, noise, seed=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit(**options).fit(data)
    assert not fit.report_["rigid_body"] and fit.model_.inverse_mass == 0.0
    found = fit.model_.modes["frequency_hz"].to_numpy()
    for f in truth.modes["frequency_hz"].to_numpy()[:3]:
        assert np.min(np.abs(found / f - 1)) < 0.02, (f, found[:4])


def test_the_low_end_rules_keep_a_free_body_and_a_grounded_one():
    """The sign rule of ModalFit's low end on exact data: a free rod (its lowest lines a
    mass line) keeps its rigid body, a fixed rod (a positive static flexibility) has none,
    and a resonance the poles missed among the lowest lines is no mass line: with the
    poles of every mode but the first, the low end of a cantilever whose first mode sits
    at line 3 is neither a rigid body nor a lower residual, and the missed mode is placed
    within a line of its frequency."""
    freq = np.linspace(0.05, 8.0, 800)
    omega = 2 * np.pi * freq
    w = np.ones_like(omega)
    for support, rigid in (("free", True), ("fixed", False)):
        model = Rod(1.0, 1.0, support=support).modal_model(10, damping_ratio=0.01)
        fit = ModalFit()
        assert fit._low_end(omega, model.frf(omega), w, model.poles, False)[0] is rigid
        assert fit._low_resonance(omega, model.frf(omega), model.poles) is None
    beam = CantileverBeam(1.0, 1.0).modal_model(10, damping_ratio=0.01)
    f1 = beam.modes["frequency_hz"].iloc[0]
    freq = np.arange(1, 2000) * f1 / 3.0
    omega = 2 * np.pi * freq
    h, rest = beam.frf(omega), beam.poles[np.abs(beam.poles) > 1.5 * 2 * np.pi * f1]
    fit = ModalFit()
    assert fit._low_end(omega, h, np.ones_like(omega), rest, False) == (False, False)
    placed = fit._low_resonance(omega, h, rest)
    assert abs(placed.imag / (2 * np.pi) - f1) < f1 / 3.0



@pytest.mark.parametrize("noise", [0.0, 0.01])
def test_a_driving_point_measured_above_its_only_mode_is_its_lower_residual(noise):
    """A 2 kg spring-mass (10 Hz) measured on 15-40 Hz: no resonance in the band, its
    lowest lines falling as ``omega^-2.8``, steeper than any mass line. They were fitted
    as a 1.6 kg rigid body and a constant (32 % off at 15 Hz, the passive fit refused as
    "not a driving point"); the lower residual mode holds the mode below the band: exact
    without noise, the mass within 1 % at 1 % noise, and a driving point."""
    from data_synth import SpringMass

    body = SpringMass(2.0, 2.0 * (2 * np.pi * 10.0) ** 2, damping_ratio=0.01)
    data = synthetic_frf(body, np.linspace(15.0, 40.0, 300), quantity="receptance",
                         noise=noise, seed=1)
    with pytest.warns(ModalFitWarning, match="no resonance"):
        fit = ModalFit().fit(data)
    report = fit.report_
    assert report["verdict"] == "ok" and report["driving_point"]
    assert report["lower_residual_mode"] and not report["rigid_body"]
    assert report["frf_nrmse"] < (1e-12 if noise == 0 else 1.5 * noise)
    assert report["effective_mass"] == pytest.approx(2.0, rel=1e-12 if noise == 0 else 0.01)


def _real(name):
    from modalid import read_frf

    if name.endswith(".mat"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")              # coherence clipped at a few lines
            return read_frf(DATA / name, quantity="accelerance")
    n = sum(1 for _ in open(DATA / name))
    return read_frf(DATA / name, format="complex-lines", freq_hz=np.arange(float(n)),
                    quantity="accelerance")


@pytest.mark.parametrize("name, published, tol", [
    # case2's issue target is 0.1 %: 192.669 Hz, 0.04 % from vibration_toolbox's 192.594
    # (a peak narrower than its 0.3125 Hz lines, coherence 0.1-0.5 there); 192.396 Hz
    # (0.103 %) before the selection's backward elimination
    ("case1.mat", [212.09], 1e-3), ("case2.mat", [192.59], 1e-3),
    # pyuff's peaks, the first where 1/H crosses zero between its lines 51 and 52 Hz
    ("meas_point_1.txt", [51.52, 142, 279, 460, 687, 959], 5e-3),
    # point 2: no pole at its 417 Hz antiresonance (one the weights trusted beyond the
    # data's noise there, dropped by its local evidence)
    ("meas_point_2.txt", [51.52, 142, 279, 460, 687, 959], 5e-3),
    ("meas_point_3.txt", [51.52, 142, 279, 460, 687, 959], 5e-3)])
def test_real_files_with_no_options(name, published, tol):
    """Measured transfer FRFs, ModalFit() with no options: the band, the weighting and
    'not a driving point' decided from the data, every published resonance found, none
    spurious in the pyuff beam, and the verdict not failed."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit().fit(_real(name))
    r = fit.report_
    found = r["modes"]["frequency_hz"].to_numpy()
    for f in published:
        assert np.min(np.abs(found / f - 1)) < tol, (f, found)
    assert r["driving_point"] is False and r["verdict"] != "failed"
    assert r["band_hz"][0] > 0 and r["band_reason"]
    if name.startswith("meas"):
        assert r["n_modes"] == 6 and r["weighting"] == "relative"
        assert r["band_hz"][0] >= 5.0                    # the noisy lowest lines dropped
        # peaks sharper than the 1 Hz lines: their damping is flagged, not trusted
        assert (~r["modes"]["damping_resolved"]).sum() >= 3
    else:
        assert r["weighting"] == "noise"                 # an analyzer's noise floor


@pytest.mark.parametrize("freq_range", [(150, 260), (180, 205), (100, 300), (20, 400)])
def test_a_sharp_peak_on_a_noise_floor_is_a_mode_on_the_bands_a_user_chooses(freq_range):
    """vtb case2 on the issue's own bands: its one resonance, one line 10 times its
    neighbours (192.5 Hz) on a noise floor of about 30 %, at coherence 0.1-0.5. The
    missed-mode search judged the peak against a noise proportional to the data's own
    height there, the peak's: 3 "sigma" per line, not taken (no mode, verdict failed on
    three of these bands). Judged against the noise of the lines without the mode, it is a
    mode within 0.11 % of vibration_toolbox's 192.59 Hz, and nothing else is fitted."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit(freq_range=freq_range).fit(_real("case2.mat"))
    f = fit.report_["modes"]["frequency_hz"].to_numpy()
    assert f.size == 1 and abs(f[0] / 192.59 - 1) < 1.1e-3, f
    assert fit.report_["verdict"] != "failed"


def test_correlated_residuals_widen_the_standard_deviations():
    """Bartlett's factor: 1 for white residuals, sqrt((1 + rho)/(1 - rho)) for AR(1) ones;
    on noise alone the fit keeps its stds (inflation near 1), on a measured FRF whose
    residual is model error it widens them."""
    from modalid._report import residual_correlation_inflation

    rng = np.random.default_rng(0)
    white = rng.normal(size=20000) + 1j * rng.normal(size=20000)
    assert residual_correlation_inflation(white) == pytest.approx(1.0, abs=0.02)
    ar = np.zeros(20000, complex)
    for k in range(1, ar.size):
        ar[k] = 0.8 * ar[k - 1] + white[k]
    assert residual_correlation_inflation(ar) == pytest.approx(3.0, rel=0.05)
    assert residual_correlation_inflation(np.zeros(5)) == 1.0
    _, _, _, fit = fitted("fixed rod", 0.05)
    assert 1.0 <= fit.report_["std_inflation"] < 1.1
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        measured = ModalFit().fit(_real("case1.mat"))
    assert measured.report_["std_inflation"] > 1.5


def test_a_mode_whose_lines_the_model_misses_has_its_standard_deviations_widened():
    """The formula's variance is the band's mean residual; where a mode's own lines are
    missed by more than noise explains (chi-square, 99 %) its stds grow by the local rms
    over the band's. On noise alone about 1 % of the modes are widened; vtb's sharp
    analyzer peaks (missed 32 and 100 times the band's mean) are, and their sub-band
    refits then differ from the whole band's by about their std (7 and 2.5 before)."""
    from modalid._report import local_misfit_inflation, residual_correlation_inflation

    rng = np.random.default_rng(1)
    omega = np.linspace(1.0, 1000.0, 4000)
    white = rng.normal(size=omega.size) + 1j * rng.normal(size=omega.size)
    poles = -0.5 + 1j * rng.uniform(50.0, 950.0, 300)
    assert np.mean(local_misfit_inflation(omega, white, poles) > 1.0) < 0.03
    # correlated noise (3 taps, Bartlett's factor 2.2): its lines count less
    taps = white[2:] + white[1:-1] + white[:-2]
    bartlett = residual_correlation_inflation(taps)
    assert np.mean(local_misfit_inflation(omega[2:], taps, poles,
                                          correlation=bartlett) > 1.0) < 0.03
    bad = white.copy()
    near = np.abs(omega - 500.0) <= 5 * np.median(np.diff(omega))
    bad[near] = np.sqrt(100.0)                      # 50 times the noise's mean power, 2
    factor = local_misfit_inflation(omega, bad, np.array([-0.1 + 500j, -0.1 + 200j]))
    share = near.sum() / omega.size                  # the band's mean holds the excess too
    assert factor[0] == pytest.approx(np.sqrt(50.0 / (1.0 + 49.0 * share)), rel=0.05)
    assert factor[1] == 1.0
    _, _, _, fit = fitted("fixed rod", 0.05)
    assert not any("misses its lines" in note for note in fit.report_["notes"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        case2 = ModalFit().fit(_real("case2.mat"))
    assert any("misses its lines" in note for note in case2.report_["notes"])
    mode = case2.report_["modes"].iloc[np.argmin(abs(case2.report_["modes"]["frequency_hz"]
                                                     - 192.4))]
    assert mode["frequency_hz_std"] > 0.02            # 0.0034 Hz before: 0.2 Hz from vtb's


def test_the_fit_plot_shows_the_quantity_measured_with_phase_and_coherence():
    """Accelerance with coherence: the plot is in accelerance (not the receptance fitted),
    with the phase and the coherence on Axes of their own; one Axes given: magnitude only."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    truth = ModalModel.from_modes(2 * np.pi * np.array([10.0, 25.0]), [0.01, 0.02],
                                  [1.0, 2.0])
    freq = np.linspace(1.0, 40.0, 400)
    coherence = np.clip(0.9 + 0.1 * np.cos(freq), 0.0, 1.0)
    data = FRFData(freq, truth.frf(2 * np.pi * freq, quantity="accelerance"),
                   quantity="accelerance", coherence=coherence)
    fit = ModalFit().fit(data)
    magnitude = fit.plot_fit()
    assert len(magnitude.figure.axes) == 3
    phase, coh = magnitude.figure.axes[1:]
    assert "accelerance" in magnitude.get_ylabel()
    np.testing.assert_allclose(magnitude.get_lines()[0].get_ydata(), np.abs(data.values))
    assert phase.get_ylabel() == "phase (deg)" and coh.get_ylabel() == "coherence"
    np.testing.assert_allclose(coh.get_lines()[0].get_ydata(), coherence)
    _, one = plt.subplots()
    assert fit.plot_fit(ax=one) is one and len(one.get_lines()) == 2
    plt.close("all")


@pytest.mark.parametrize("seed", range(5))
def test_modes_narrower_than_a_line_are_found_from_their_peaks(seed):
    """Two modes of zeta 2e-4 (half-power widths of 0.04 and 0.07 Hz) between 0.5 Hz lines,
    1 % noise, ModalFit() with no options: both found where they lie between the lines
    (to a fiftieth of a line; the reported frequency std is the right size), the damping
    flagged as not resolved. A missed one is started from its peak's three lines (the
    root of the residual's reciprocal) and judged with the pseudo-modes refitted: held,
    they carried its skirt and the trial was lost (the fit missed one mode or both in
    three of these seeds)."""
    freq = np.arange(1, 401) * 0.5
    fn = np.array([100.13, 163.37])
    truth = ModalModel.from_modes(2 * np.pi * fn, [2e-4, 2e-4], [1.0, 2.0])
    rng = np.random.default_rng(seed)
    noise = rng.standard_normal(freq.size) + 1j * rng.standard_normal(freq.size)
    values = truth.frf(2 * np.pi * freq, quantity="accelerance") * (1 + 0.01 * noise / np.sqrt(2))
    fit = ModalFit().fit(FRFData(freq, values, quantity="accelerance"))
    modes = fit.report_["modes"]
    assert len(modes) == 2 and fit.report_["verdict"] == "ok"
    got = modes["frequency_hz"].to_numpy()
    np.testing.assert_allclose(got, fn, rtol=0, atol=0.01)
    assert np.all(np.abs(got - fn) < 5 * modes["frequency_hz_std"].to_numpy())
    assert not modes["damping_resolved"].any()


@pytest.mark.parametrize("seed", [0, 1])
def test_a_damping_the_lines_cannot_resolve_is_not_left_at_the_bound(seed):
    """Three all but undamped modes (zeta 1e-7: half-power widths of 1e-5 Hz) between 0.5
    Hz lines, 1 % noise: every damping fits the lines alike down to zero, and the
    refinement took some of them to its bound (1e-9, verdict suspect). Such a mode keeps
    its frequency (to 0.002 Hz) and gets the largest small damping that fits as well (a
    half-power bandwidth of at most a quarter of a line), flagged not resolved, with a
    note; the verdict is ok."""
    freq = np.arange(1, 601) * 0.5
    fn = np.array([100.13, 163.37, 251.71])
    truth = ModalModel.from_modes(2 * np.pi * fn, [1e-7] * 3, [1.0, 2.0, 1.5])
    rng = np.random.default_rng(seed)
    noise = rng.standard_normal(freq.size) + 1j * rng.standard_normal(freq.size)
    values = truth.frf(2 * np.pi * freq, quantity="accelerance") * (1 + 0.01 * noise / np.sqrt(2))
    fit = ModalFit().fit(FRFData(freq, values, quantity="accelerance"))
    modes, report = fit.report_["modes"], fit.report_
    assert len(modes) == 3 and report["verdict"] == "ok", report["verdict_reasons"]
    np.testing.assert_allclose(modes["frequency_hz"], fn, rtol=0, atol=0.002)
    zeta = modes["damping_ratio"].to_numpy()
    assert np.all(zeta > 1e-6), zeta
    assert np.all(2 * zeta * fn <= 0.25 * 0.5 * (1 + 1e-9)), zeta
    assert not modes["damping_resolved"].any()
    moved = [n for n in report["notes"] if "do not resolve it" in n]
    assert moved and all("bound" in n for n in moved)

@pytest.mark.parametrize("freq_range", [(2, 701), (2, 1000), (20, 1000)])
def test_a_reweighting_that_chases_lines_the_data_do_not_follow_is_not_kept(freq_range):
    """pyuff point 1 on a band the user chose to start at 2 Hz (lines whose accelerance
    phase is noise, carried to receptance) or at 20 Hz: reweighting by the model
    ``1/|H_model|`` gave a few lines most of the cost (its own cost 3e5), the poles ran
    to damping 0.5-0.7 and every mode was dropped as not
    significant ("no resonance found", verdict failed). A reweighted refinement is kept
    only when its cost weighted by the data at most doubles (27 -> 59 here: 2.2 times),
    else the fit weighted by the data is converged in full: every peak in the band is
    found within 0.5 %, the refinement converged and the verdict is ok."""
    peaks = np.array([51.52, 142.18, 278.67, 460.4, 687.17, 958.53])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit(freq_range=freq_range).fit(_real("meas_point_1.txt"))
    f = fit.report_["modes"]["frequency_hz"].to_numpy()
    expected = peaks[peaks < freq_range[1]]
    assert f.size == expected.size, f
    np.testing.assert_allclose(f, expected, rtol=5e-3)
    assert fit.report_["verdict"] == "ok" and fit.report_["converged"]


def test_fewer_modes_than_asked_are_said():
    """``n_modes`` above what the band's diagram supports gave fewer modes, silently (a
    beam's n_modes=8, 12 or 20 all its 5): said now, in the notes and a warning."""
    truth = ModalModel.from_modes(2 * np.pi * np.array([120.0, 310.0, 560.0]),
                                  [0.01, 0.01, 0.01], [2.0, 1.5, 3.0])
    data = synthetic_frf(truth, np.arange(5.0, 800.0, 0.5), noise=0.01, seed=2)
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        fit = ModalFit(n_modes=6).fit(data)
    found = len(fit.report_["modes"])
    assert found == 3
    note = "n_modes=6 asked, 3 found: the band's stabilization diagram"
    assert fit.report_["notes"][-1].startswith(note)
    assert [str(w.message) for w in said if issubclass(w.category, ModalFitWarning)
            and str(w.message).startswith(note)]
    with warnings.catch_warnings():
        warnings.simplefilter("error", ModalFitWarning)
        exact = ModalFit(n_modes=3).fit(data)
    assert not [n for n in exact.report_["notes"] if "asked" in n]


def test_a_transfer_fit_keeps_its_negative_mass_line():
    """An exact transfer receptance of a free body measured away from the hit point: a
    negative mass line (the rigid rotation outweighs the translation there) and modal
    constants of both signs. Fitted with a mass line and no passivity constraint, the
    line comes out negative, as it is; the model kept only positive ones (0 in its
    place: 50-90 % error at the lowest lines), so it no longer described the data."""
    truth = ModalModel.from_modes(2 * np.pi * np.array([120.0, 310.0, 560.0]),
                                  [0.01, 0.01, 0.01], [2.0, -1.5, 3.0], inverse_mass=-0.25)
    freq = np.arange(5.0, 800.0, 0.5)
    data = FRFData(freq, truth.frf(2 * np.pi * freq))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit(rigid_body=True, passive=False).fit(data)
    assert fit.model_.inverse_mass == pytest.approx(-0.25, rel=1e-6)
    np.testing.assert_allclose(fit.model_.frf(2 * np.pi * freq), data.values, rtol=1e-6)
    r = fit.report_
    assert r["verdict"] == "ok" and r["driving_point"] is False
    # its standard deviation is reported; "rigid body" and the effective mass speak of a
    # positive mass line (a driving point's) only
    assert 0 < r["inverse_mass_std"] < 1e-6
    assert not r["rigid_body"] and r["rigid_mass"] == np.inf
    assert r["effective_mass"] == pytest.approx(1 / (1 / 2.0 + 1 / 3.0), rel=1e-6)


@pytest.mark.parametrize("inverse_mass", [-0.2, -0.05])
def test_a_transfer_fit_whose_mass_line_a_lower_pseudo_mode_carries(inverse_mass):
    """A free body's transfer mobility from 5 Hz with every mode of one sign and a
    negative rigid term, at 5 % noise: the fit stands a lower pseudo-mode (-5 kg at 0.4
    Hz) in for the mass line, and with 1/M = 0 the decision saw three positive modes and
    called it a driving point ("ok"; impactpred took it as a body). The pseudo-mode's
    mass line (2 Re(r p)) is counted now, and it is no slight misfit: it makes 39-71 %
    of the lines below the modes."""
    truth = ModalModel.from_modes(2 * np.pi * np.array([200.0, 700.0, 1500.0]), [0.01] * 3,
                                  [1.0, 2.0, 1.5], inverse_mass=inverse_mass)
    data = synthetic_frf(truth, np.arange(5.0, 2000.0, 0.5), quantity="mobility",
                         noise=0.05, seed=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit().fit(data)
    r = fit.report_
    assert r["driving_point"] is False
    assert "the mass line a negative one" in r["driving_point_reason"]
    np.testing.assert_allclose(r["modes"]["frequency_hz"], [200.0, 700.0, 1500.0], rtol=1e-3)


def test_a_lower_pseudo_mode_near_the_band_start_is_no_mass_line():
    """A windowed hammer test of a fixed rod's driving point (accelerance, 4 hits, 2 %
    noise, decay 30 1/s): its lower pseudo-mode sits at 0.93 of the band's start, fitting
    the window's leakage there, with 2 Re(r p) = -0.34 1/kg; counted as a mass line it
    made the rod a transfer FRF, and impactpred refused it (review). Only a pole well
    below the band's start (under 0.3 of it) stands in for a mass line."""
    from data_synth import lightly_damped, synthetic_hammer_test
    from modalid import frf_from_hammer

    truth = lightly_damped(Rod(1.0, 1e-3, support="fixed"), 30, 0.005, residual=False)
    test = synthetic_hammer_test(truth, 51200.0, 0.5, n_hits=4, noise=0.02, seed=7,
                                 anti_alias=True, response="acceleration")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        est = frf_from_hammer(test.force, test.response, 51200.0, exponential_decay=30.0)
        fit = ModalFit(**est.fit_options()).fit(est.frf.band((2.0, 14000)))
    assert fit.report_["driving_point"] is True
    assert "a negative one" not in fit.report_["driving_point_reason"]


def test_a_one_hit_hammer_record_with_no_options():
    """ladisk's free beam, struck once (tests/data/acceleration.lvm.gz: force and
    acceleration at 50 kHz, MIT), its FRF by frf_from_hammer and ModalFit() with no
    options: the band ends where the hammer's force spectrum has fallen 20 dB (6.6 kHz;
    the whole 25 kHz before, 13-16 % median line error and verdict suspect), the negative
    mass line of this transfer FRF is kept (it was zeroed: 50-90 % error below the first
    mode), and the publisher's four modes (pyEMA LSCF on 1-4000 Hz: 695.0, 1897.6,
    2777.3, 3671.2 Hz, damping 0.0047, 0.0031, 0.0024, 0.0020) come out within 0.1 % and
    their damping within 5 %. The verdict is "suspect": below them, at 18 Hz, the data
    hold a sharp resonance (2.5 against 1.2 and 0.9 on the lines beside it, the force's
    spectrum smooth there: the beam on its suspension) that the model misses by 104 %
    of the data, 67 times their scatter (it was "ok", silent)."""
    import importlib.util

    path = Path(__file__).resolve().parent.parent / "benchmarks" / "real_data.py"
    spec = importlib.util.spec_from_file_location("real_data", path)
    real_data = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(real_data)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit().fit(real_data.load("ladisk beam, one hit"))
    r = fit.report_
    assert r["verdict"] == "suspect" and r["driving_point"] is False
    assert [round(f, 1) for f in r["missed_resonances_hz"]] == [18.0]
    assert 6000 < r["band_hz"][1] < 7000 and "20 dB" in r["band_reason"]
    assert fit.model_.inverse_mass < 0 and r["frf_median_relative_error"] < 0.05
    modes = r["modes"]
    f = modes["frequency_hz"].to_numpy()
    for p, z in zip([695.0, 1897.6, 2777.3, 3671.2], [0.0047, 0.0031, 0.0024, 0.0020]):
        k = int(np.argmin(np.abs(f - p)))
        assert abs(f[k] / p - 1) < 1e-3, (p, f)
        assert modes["damping_ratio"].iloc[k] == pytest.approx(z, rel=0.05)


@pytest.mark.parametrize("seed", [13])
def test_a_refinement_through_coinciding_poles_does_not_break_down(seed):
    """Two poles 1e-9 apart (a missed-mode search can add one where a pole already is) on
    a noisy FRF: Kaufman's normal matrix is singular and its rounding turned diagonals
    negative (-1.9e11 on a measured beam); scaled by them, the step overflowed to NaN and
    numpy raised "SVD did not converge" from inside the refinement (seed 13). A step that
    is not finite, or a trial the projection cannot solve, is now a rejected step: the
    refinement ends with finite poles, and says it stopped on a singular matrix where it
    did."""
    from modalid._lsfd import Terms, refine_varpro

    truth = ModalModel.from_modes(2 * np.pi * np.array([100.0, 180.0]), [0.01, 0.01],
                                  [1.0, 2.0])
    omega = 2 * np.pi * np.arange(50.0, 250.0, 0.5)
    rng = np.random.default_rng(seed)
    noise = rng.standard_normal(omega.size) + 1j * rng.standard_normal(omega.size)
    h = truth.frf(omega) * (1 + 0.05 * noise)
    p = truth.poles
    start = np.array([p[0], p[1], p[1] * (1 + rng.uniform(-1e-9, 1e-9))])
    poles, x, info = refine_varpro(omega, h, 1 / np.abs(h), start,
                                   Terms(np.zeros(0), False, False, 0.0))
    assert np.all(np.isfinite(poles)) and np.all(np.isfinite(x))
    np.testing.assert_allclose(np.sort(np.abs(poles))[[0, -1]], np.abs(p), rtol=2e-3)
    # where the rounding makes the normal matrix singular (this seed's did with the
    # numpy of the test's writing), the refinement stops and says so; with numpy 2.4.6
    # it converges through
    assert info["converged"] or "singular" in info["message"]


@pytest.mark.parametrize("method", ["vf", "lscf"])
def test_a_band_of_a_few_lines_is_fitted_not_crashed(method):
    """pyuff point 2 on 960.5-965.6 Hz: six lines above its 958.5 Hz resonance. Vector
    fitting's relocation system then has more unknowns than rows, and scipy's "expected
    square matrix" came out of ModalFit.fit (found by fitting random bands of the real
    files); it takes the minimum-norm solution: the fit holds residual terms only and
    says the band has no resonance."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit(freq_range=(960.4984566653256, 965.6042272713113),
                       method=method).fit(_real("meas_point_2.txt"))
    assert fit.report_["n_modes"] == 0 and fit.report_["verdict"] != "failed"
    assert fit.report_["frf_nrmse"] < 0.1


def test_a_passive_fit_the_verdict_passes_is_no_stall():
    """The benchmark's cantilever measured by a synthetic hammer test, 10 modes, 5 % noise,
    seed run 16 of the coverage study: the passive fit's median line error is 16.6 %
    against 10.0 % for the unconstrained one, which holds a noise mode of -203 kg. That
    was taken for a stall (over 1.5 times the unconstrained error): the unconstrained
    fit stood, "ok" but no driving point, and impactpred refused the body as a transfer
    FRF. The passive fit is "ok" by the verdict's own standard (the data's scatter is
    6.2 %): it stands, a driving point, every modal mass positive. (Since the record
    end's terms are taken out and the fit repeated, 4.3 % of the lowest lines here, its
    median line error is 9.8 %.)"""
    from impactpred._benchmark_cases import benchmark_cases, measure_body
    from impactpred.benchmark import body_seed

    beam = {c.key: c for c in benchmark_cases()}["rod-cantilever"].body2
    fit = measure_body(beam, 10, 0.05, seed=body_seed(beam, 10, 0.05, 16)).fit
    report = fit.report_
    assert report["driving_point"] and report["verdict"] == "ok"
    assert np.all(report["modes"]["modal_mass"].to_numpy() > 0)
    assert report["frf_median_relative_error"] < 3 * report["noise_median_relative"]
    assert report["record_end_removed"] > 0.01


def test_a_fixed_rod_accelerance_with_a_mode_just_above_its_band_is_a_driving_point():
    """A fixed rod's driving-point accelerance with three modes in band and the fourth
    just above its top (1 % noise; found by predicting impacts from random synthetic FRF
    files): the unconstrained fit is right (masses 0.1964 for 0.19645) and passive by
    itself, but the passive fit started afresh stalled at 20.9 % median line error
    (its upper pseudo-modes dropped), so the FRF was called "not a passive driving point"
    and the impact refused. An unconstrained fit that satisfies the constraint is the
    constrained optimum: it stands, as a driving point, and the report says why. (Since
    the less persistent candidates are judged too, the passive fit of this FRF no longer
    stalls and the outcome is reached directly; the rule itself is checked by
    :func:`test_a_discarded_passive_fit_says_nothing`.)"""
    from data_synth import lightly_damped, synthetic_frf

    rod = Rod(0.3928963509214992, 1.8631548819449462, support="fixed")
    freq = np.linspace(0.823965392238586 / 2000, 0.823965392238586, 2000)
    frf = synthetic_frf(lightly_damped(rod, 8, 1.5e-4), freq, quantity="accelerance",
                        noise=0.01, seed=45)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit().fit(frf)
    r = fit.report_
    assert r["driving_point"] is True
    np.testing.assert_allclose(r["modes"]["modal_mass"], rod.modal_model(3).modes[
        "modal_mass"], rtol=2e-3)
    assert r["verdict"] == "ok" and fit.model_.is_passive()


def _random_case_frf(body, zeta, top, *, quantity, noise, seed, low=None):
    """A case of benchmarks/random_predictions.py: the driving-point FRF of ``body``'s
    first 300 modes at damping ratio ``zeta`` on 2000 lines from ``low`` (default
    ``top / 2000``) to ``top`` Hz, in ``quantity``, with ``noise``."""
    from data_synth import lightly_damped, synthetic_frf

    low = top / 2000 if low is None else low
    return synthetic_frf(lightly_damped(body, 300, zeta), np.linspace(low, top, 2000),
                         quantity=quantity, noise=noise, seed=seed)


def test_a_probe_whose_junk_poles_carry_the_sign_does_not_decide():
    """A free rod's driving-point accelerance, 11 modes in band, 1 % noise
    (benchmarks/random_predictions.py seed 3, case 28): the quick unconstrained probe kept
    two junk pole pairs at damping 0.5-0.6 with modal masses -0.12 and -1.1 kg, 29 % of
    the modes' strength 1/|m|, and called the FRF a transfer FRF; the full unconstrained
    fit that then stood had dropped them (they left the band) and its 11 modes were all
    positive, yet the impact was refused. The fit that stands now decides: a driving
    point, its modes the rod's."""
    rod = Rod(0.9802501951719393, 1.0731951295241557)
    top = 5.363303936502078
    frf = _random_case_frf(rod, 2.626688781396768e-4, top, quantity="accelerance",
                           noise=0.01, seed=28)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit().fit(frf)
    r = fit.report_
    assert r["driving_point"] is True and "the full unconstrained fit" in r[
        "driving_point_reason"]
    exact = rod.modal_model(12).modes
    exact = exact[exact["frequency_hz"] < top]
    assert len(r["modes"]) == len(exact) == 11
    np.testing.assert_allclose(r["modes"]["frequency_hz"], exact["frequency_hz"], rtol=1e-4)
    np.testing.assert_allclose(r["modes"]["modal_mass"], exact["modal_mass"], rtol=0.02)
    assert r["verdict"] == "ok" and fit.model_.is_passive()


def _ends_left_to_the_pseudo_modes(h, resid):
    """The missed-mode search's lines at the band's ends as they were before it looked
    at a resonance missed there: the 2 % at either end, all (``_edge_lines``' stand-in
    for the tests whose fits weighted 1/|H| failed or stalled for a mode lost there)."""
    edge = np.zeros(h.size, bool)
    n = int(0.02 * h.size)
    edge[:n] = True
    edge[h.size - n:] = True
    return edge


def test_a_failed_fit_weighted_by_the_frf_is_refitted_by_the_scatter(monkeypatch):
    """A cantilever's driving-point mobility measured from 3 times its first mode, 3 %
    noise (benchmarks/random_predictions.py seed 4, case 45 from 2.42 Hz): its modes are
    far narrower than the 0.14 Hz lines (one line stands 40 times above its neighbours).
    Weighted 1/|H| (``weighting="auto"``'s choice for proportional noise) the fit lost the
    two lowest modes and its pseudo-modes cancelled to a model near zero below 50 Hz
    (error 95 %, "failed"; the impact was refused). The failed fit is refitted weighted
    by the data's scatter, which stands: the ten modes in band, a driving point. (Since
    the missed-mode search looks at a resonance missed at the band's ends, the 1/|H| fit
    keeps its lowest mode and was "suspect", its passive fit stalling: the refit stood
    too. Since session #36 that fit, which missed the band's lowest lines with no term
    below the band, is refitted with the lower residual: "ok" weighted 1/|H|, the ten
    modes within 2e-4. The search as it was, the ends left to the pseudo-modes,
    reproduces the failed fit.)"""
    import modalid._pole_checks

    beam = CantileverBeam(4.1625533859322355, 0.7037545381520051)
    frf = _random_case_frf(beam, 2.596307205355822e-4, 280.08354970973886,
                           low=2.423185040657117, quantity="mobility", noise=0.03, seed=45)
    exact = beam.modal_model(12).modes["frequency_hz"].to_numpy()
    exact = exact[(exact > 2.43) & (exact < 280.0)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        today = ModalFit().fit(frf).report_
    assert today["weighting"] == "relative" and today["verdict"] == "ok"
    assert today["lower_residual_mode"] and today["driving_point"]
    assert any(n.startswith("refitted with the lower residual") for n in today["notes"])
    np.testing.assert_allclose(today["modes"]["frequency_hz"], exact, rtol=2e-3)
    monkeypatch.setattr(modalid._pole_checks, "_edge_lines", _ends_left_to_the_pseudo_modes)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit().fit(frf)
        relative = ModalFit(weighting="relative").fit(frf)
    assert relative.report_["verdict"] == "failed"
    r = fit.report_
    assert r["weighting"] == "noise" and r["weighting_reason"].startswith(
        "the fit weighted 1/|H| failed (the FRF error")
    assert r["verdict"] == "ok" and r["driving_point"] is True
    np.testing.assert_allclose(r["modes"]["frequency_hz"], exact, rtol=2e-3)


def test_a_stalled_passive_fit_weighted_by_the_frf_is_refitted_by_the_scatter():
    """A fixed rod's accelerance measured from above its second mode (0.459-1.697 Hz, 4
    modes, 3 % noise; benchmarks/random_predictions.py seed 5, case 41 from 0.459 Hz):
    weighted 1/|H| the unconstrained fit's modes are all of positive mass but it is not
    passive (two upper pseudo-modes), and the passive fit stalled at 21.5 % median error
    against 6.4 %: "not a passive driving point", the impact refused. Refitted weighted
    by the data's scatter: a passive driving point at 6.9 % with the same 4 modes, which
    stands (within the verdict's tolerance, 9 %). The stall came from the low end read as
    a rigid body (its lowest lines fall faster than a mass line: the two modes below);
    read as their lower residual (the default since session #36) the 1/|H| fit is a
    passive driving point itself, "ok" at 5.9 %, so the stall is reproduced here with
    ``rigid_body=True`` (whose refit is "suspect" now: it misses the band's lowest lines,
    where the rigid body forced is not the data's). (Session #20's case, a cantilever's
    accelerance whose lowest modes were under-resolved, seed 6, case 23, no longer
    stalls: the 1/|H| fit finds its 1.32 Hz mode at line 19, since the search looks at
    the band's ends, and is a passive driving point at 2.5 %.)"""
    rod = Rod(1.0580912101302862, 1.6774046834283156, support="fixed")
    frf = _random_case_frf(rod, 1.102228806533333e-4, 1.6966330275142365,
                           low=0.45871625834587876, quantity="accelerance", noise=0.03,
                           seed=41)
    exact = rod.modal_model(12).modes["frequency_hz"].to_numpy()
    exact = exact[(exact > 0.46) & (exact < 1.69)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        default = ModalFit().fit(frf)
        fit = ModalFit(rigid_body=True).fit(frf)
    r = default.report_
    assert r["weighting"] == "relative" and r["lower_residual_mode"] and not r["rigid_body"]
    assert r["driving_point"] is True and default.model_.is_passive()
    assert r["verdict"] == "ok" and r["frf_median_relative_error"] < 0.08
    np.testing.assert_allclose(r["modes"]["frequency_hz"], exact, rtol=1e-4)
    r = fit.report_
    assert r["driving_point"] is True and fit.model_.is_passive()
    assert r["weighting"] == "noise" and r["weighting_reason"].startswith(
        "the fit weighted 1/|H| was no passive driving point (4 of 4 modes have a "
        "positive modal mass")
    np.testing.assert_allclose(r["modes"]["frequency_hz"], exact, rtol=1e-4)
    # the rigid body forced is not the data's low end: its lowest lines missed, "suspect"
    assert r["verdict"] == "suspect" and r["frf_median_relative_error"] < 0.08
    assert r["missed_low_end_hz"][0] == r["band_hz"][0]
    beam = CantileverBeam(4.75823437772677, 2.649254637747698)
    frf = _random_case_frf(beam, 2.621833890804686e-4, 130.42020105858865,
                           quantity="accelerance", noise=0.03, seed=23)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        today = ModalFit().fit(frf)
    assert today.report_["driving_point"] is True and today.model_.is_passive()
    assert today.report_["verdict"] == "ok" and len(today.report_["modes"]) == 15
    assert today.report_["frf_median_relative_error"] < 0.03


def test_a_refit_by_the_scatter_that_does_no_better_is_not_kept(monkeypatch):
    """A fixed rod's exact FRF at zeta 1e-2, 40 overlapping modes on 2401 lines: with two
    passes of the missed-mode search (as before a search stopped by its budget got more),
    weighted 1/|H| the fit fails (an infinite modal mass) at 0.8 % error; refitted by the
    scatter it is "suspect" at 29 % (3 of 40 modes). The first fit stands, restored
    whole, and its report says a refit was tried. With the default passes: all 40 modes,
    exact."""
    from data_synth import lightly_damped, synthetic_frf

    from modalid import _frf_pipeline

    truth = lightly_damped(Rod(1.0, 1e-3, support="fixed"), 80, 1e-2)
    frf = synthetic_frf(truth, np.linspace(1.0, 20000.0, 2401))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        full = ModalFit().fit(frf).report_
        monkeypatch.setattr(_frf_pipeline, "_MAX_PASSES", 2)
        fit = ModalFit().fit(frf)
    assert full["verdict"] == "ok" and full["frf_nrmse"] < 1e-3
    np.testing.assert_allclose(full["modes"]["frequency_hz"], 250.0 + 500.0 * np.arange(40),
                               rtol=2e-4)
    np.testing.assert_allclose(full["modes"]["damping_ratio"], 1e-2, rtol=2e-2)
    r = fit.report_
    assert r["weighting"] == "relative" and r["verdict"] == "failed"
    assert r["weighting_reason"].endswith("; a refit weighted by the data's own scatter "
                                          "did no better")
    assert r["frf_nrmse"] < 0.02 and len(r["modes"]) > 20
    assert not {"_weighting_forced", "_passive_stalled"} & set(fit.__dict__)
    np.testing.assert_allclose(fit.predict(frf.omega), frf.values,
                               atol=0.05 * np.abs(frf.values).max())


def test_warnings_said_again_keep_their_module():
    """The fit's warnings are recorded and said again for the fit that stands: a numerical
    one raised inside modalid keeps its module, so that ``error::RuntimeWarning:modalid.*``
    (the test configuration's filter) still turns it into an error; a ModalFitWarning is
    said at the caller."""
    from modalid import _lsfd
    from modalid._fit_one import _say_again

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        warnings.warn_explicit("overflow", RuntimeWarning, _lsfd.__file__, 10,
                               module="modalid._lsfd")
        warnings.warn("no resonance", ModalFitWarning, stacklevel=1)
    with warnings.catch_warnings():
        warnings.filterwarnings("error", category=RuntimeWarning, module="modalid.*")
        with pytest.raises(RuntimeWarning, match="overflow"):
            _say_again(caught[:1])
    with warnings.catch_warnings(record=True) as again:
        warnings.simplefilter("always")
        _say_again(caught[1:])
    assert [w.category for w in again] == [ModalFitWarning]


def test_a_mode_missed_near_the_band_bottom_does_not_hide_the_low_end():
    """A cantilever's accelerance measured from 3.5 times its first mode, 1 % noise
    (benchmarks/random_predictions.py seed 7, case 45 from 0.52 Hz): its second mode, at
    0.93 Hz, is sharp and was missed by the poles, and the lines judging the low end (up
    to half the first pole, 1.3 Hz) held its resonance: no mass line was found for the
    first mode below the band, the fits missed the lines by 22 % and the FRF was refused
    as not a passive driving point. The low end is now judged below the data's first
    resonance peak: a driving point, its modes from the third on the beam's, masses
    included (m/4 at the tip). The 0.93 Hz mode itself, at line 11 of 2000 (in the 2 %
    at the band's end the missed-mode search left to the pseudo-modes, then), is found
    since the search looks at a distinct resonance peak of the data there too."""
    from data_synth import lightly_damped, synthetic_frf

    beam = CantileverBeam(0.7939172801757642, 3.775289294499222)
    truth = lightly_damped(beam, 300, 1.0736555017374746e-4)
    f1 = np.abs(np.asarray(truth.poles)).min() / (2 * np.pi)
    frf = synthetic_frf(truth, np.linspace(3.514539007505694 * f1, 76.93061704056412, 2000),
                        quantity="accelerance", noise=0.01, seed=45)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit().fit(frf)
    r = fit.report_
    assert r["verdict"] == "ok" and r["driving_point"] is True
    assert r["rigid_body"] or r["lower_residual_mode"]
    exact = beam.modal_model(14).modes
    exact = exact[(exact["frequency_hz"] > 0.6) & (exact["frequency_hz"] < 76.9)]
    np.testing.assert_allclose(r["modes"]["frequency_hz"], exact["frequency_hz"], rtol=1e-4)
    np.testing.assert_allclose(r["modes"]["modal_mass"], exact["modal_mass"], rtol=0.02)


def _spring_mass_accelerance(noise=0.03):
    """A spring-mass's accelerance to 2.6 times its mode, 3 % noise (seed 2, case 39 of
    benchmarks/random_predictions.py)."""
    from data_synth import SpringMass, lightly_damped, synthetic_frf

    model = lightly_damped(SpringMass(1.773799480628025, 920663.2681301013), 1,
                           3.2432325744324555e-4)
    freq = np.linspace(297.7377776232762 / 2000, 297.7377776232762, 2000)
    return model, synthetic_frf(model, freq, quantity="accelerance", noise=noise, seed=39)


def test_a_driving_points_impulse_response_does_not_start_against_the_force():
    """The passive fit of a spring-mass's noisy accelerance kept its upper pseudo-mode's
    real residue: ``h(0) = sum 2 Re r = -1.26e-6`` m/(N s), a 1/s term, an impulse
    response that starts against the force (a mobility not passive at high frequency),
    refused by both impact solvers. The passivity bounds (``Im r <= 0``) do not see it;
    once the poles are found the fit holds ``h(0) = 0`` (exact for any structure) and
    says so; the mode is unchanged."""
    truth, frf = _spring_mass_accelerance()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit().fit(frf)
    r, model = fit.report_, fit.model_
    assert r["driving_point"] is True and r["verdict"] == "ok" and model.is_passive()
    jump = 2 * np.sum(model.residues.real)
    assert abs(jump) <= 1e-12 * np.abs(model.residues).sum()
    assert any("held at 0 at t = 0" in note for note in r["notes"])
    mode = r["modes"].iloc[np.argmin(np.abs(r["modes"]["frequency_hz"] - 114.66))]
    assert mode["frequency_hz"] == pytest.approx(truth.modes["frequency_hz"][0], rel=1e-3)
    assert mode["modal_mass"] == pytest.approx(1.773799480628025, rel=0.02)
    # a fit whose h(0) is positive already is left as it is (no note)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        clean = ModalFit().fit(_spring_mass_accelerance(noise=0.0)[1])
    assert not any("held at 0 at t = 0" in note for note in clean.report_["notes"])
    assert 2 * np.sum(clean.model_.residues.real) >= 0


def test_a_discarded_passive_fit_says_nothing():
    """A fixed rod's exact (undamped) accelerance: the passive fit fails on it (median
    error 100 %, "no resonance found in the band") and the unconstrained fit, which finds
    all 24 modes and is passive itself, stands. The discarded fit's warning had been said
    beside the mode table. (On 0.005-10 Hz, where this was found, the passive fit no
    longer fails with numpy 2.4.6.)"""
    freq = np.arange(0.005, 12.0, 0.01)
    rod = Rod(1.0, 1.0, support="fixed")
    data = FRFData(freq, rod.frf(2 * np.pi * freq, quantity="accelerance"),
                   quantity="accelerance")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fit = ModalFit().fit(data)
    np.testing.assert_allclose(fit.report_["modes"]["frequency_hz"], 0.25 + 0.5 * np.arange(24),
                               rtol=1e-6)
    assert "which satisfies the passivity constraint itself" in fit.report_[
        "driving_point_reason"]
    assert not [w for w in caught if "no resonance found" in str(w.message)]


def test_a_mode_at_the_band_top_is_found():
    """A mode whose peak lies in the 2 % of the lines at either end of the band, which the
    missed-mode search left to the pseudo-modes, is found when the data show it as a
    distinct resonance peak (benchmarks/random_predictions.py: 12 of 708 files of seeds
    1-10 lost such a mode, 9 with the verdict "ok"; the band's bottom:
    test_a_mode_missed_near_the_band_bottom_does_not_hide_the_low_end). A cantilever's
    receptance to 13.232 Hz, 3 % noise: its 13.2 Hz mode, 5 lines from the top, was
    missing (seed 1, case 15)."""
    beam, zeta, top = (CantileverBeam(2.6980215218848573, 1.4577394790315046),
                       1.842436781541699e-4, 13.232006593718095)
    frf = _random_case_frf(beam, zeta, top, quantity="receptance", noise=0.03, seed=15)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit().fit(frf)
    r = fit.report_
    exact = beam.modal_model(20).modes
    exact = exact[(exact["frequency_hz"] > frf.freq_hz[0])
                  & (exact["frequency_hz"] < frf.freq_hz[-1])]
    assert len(r["modes"]) == len(exact)
    np.testing.assert_allclose(r["modes"]["frequency_hz"], exact["frequency_hz"], rtol=1e-4)
    np.testing.assert_allclose(r["modes"]["modal_mass"], exact["modal_mass"], rtol=0.02)
    assert r["verdict"] == "ok" and r["missed_resonances_hz"] == []


def test_a_fit_weighted_by_the_frf_that_misses_a_resonance_is_refitted_by_the_scatter():
    """A cantilever's accelerance, 13 modes, 3 % noise (benchmarks/random_predictions.py
    seed 7, case 22): weighted 1/|H| the fit put the 0.7275 Hz mode, far narrower than
    the 0.028 Hz lines, at 0.7055 Hz with damping 0.005, and missed the data's peak by
    130 % (10 times their scatter and more at its three lines): "suspect", the data's
    resonance missed. Refitted weighted by the data's scatter: "ok", every mode within
    0.2 % (the first, 4 lines above the band's bottom, 0.17 % off; the others 3e-4)."""
    beam = CantileverBeam(4.10748982291343, 4.820319126617792)
    frf = _random_case_frf(beam, 1.2630463610044653e-4, 55.55699112571345,
                           quantity="accelerance", noise=0.03, seed=22)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        relative = ModalFit(weighting="relative").fit(frf)
        fit = ModalFit().fit(frf)
    assert relative.report_["verdict"] == "suspect"
    missed = relative.report_["missed_resonances_hz"]
    assert len(missed) == 1 and abs(missed[0] - 0.7275) < 0.03
    assert any("resonance at 0.72" in why for why in relative.report_["verdict_reasons"])
    r = fit.report_
    assert r["weighting"] == "noise" and r["weighting_reason"].startswith(
        "the fit weighted 1/|H| missed the data's resonance at 0.72")
    exact = beam.modal_model(20).modes
    exact = exact[exact["frequency_hz"] < 55.5]
    assert r["verdict"] == "ok" and len(r["modes"]) == len(exact) == 13
    np.testing.assert_allclose(r["modes"]["frequency_hz"], exact["frequency_hz"], rtol=2e-3)


def test_a_suspect_fit_weighted_by_the_frf_is_refitted_by_the_scatter(tmp_path):
    """A cantilever's mobility, 16 modes, 1 % noise, written to a CSV file and read back
    (benchmarks/random_predictions.py seed 8, case 22): weighted 1/|H| the first mode
    came out at 0.108 Hz for 0.116 (the band's third line), which misses its peak, the
    largest of the FRF: error 70.8 %, median line error 0.9 %, "suspect". Refitted
    weighted by the data's scatter: "ok" at 0.26 %, every mode within 0.3 %, and the
    refit stands. (The 1/|H| fit's path turns on the rounding: the same FRF not through
    the file, 4e-16 apart, is fitted "ok" at 0.33 % weighted 1/|H|; the rule itself:
    test_which_refit_by_the_scatter_stands.)"""
    from data_synth import lightly_damped, synthetic_frf
    from modalid import read_frf, write_frf

    beam = CantileverBeam(4.1466469350266735, 4.8244126928207445)
    top = 78.61323017313646
    write_frf(tmp_path / "case22.csv", synthetic_frf(
        lightly_damped(beam, 300, 8.82847733818296e-4), np.linspace(top / 2000, top, 2000),
        quantity="mobility", noise=0.01, seed=22))
    frf = read_frf(tmp_path / "case22.csv")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        relative = ModalFit(weighting="relative").fit(frf).report_
        fit = ModalFit().fit(frf)
    r = fit.report_
    if relative["verdict"] == "suspect":
        assert r["weighting"] == "noise" and r["weighting_reason"].startswith(
            "the fit weighted 1/|H| was suspect (the FRF error is")
    exact = beam.modal_model(20).modes
    exact = exact[exact["frequency_hz"] < 78.6]
    assert r["verdict"] == "ok" and r["frf_nrmse"] < 0.01 and len(r["modes"]) == len(exact)
    np.testing.assert_allclose(r["modes"]["frequency_hz"], exact["frequency_hz"], rtol=3e-3)


def test_which_refit_by_the_scatter_stands():
    """The rule of :func:`modalid._fit_one._refit_stands` on reports whose answer is known:
    a failed refit never; after a stall a driving point with as many modes or fewer
    resonances missed; for a missed
    resonance one that misses fewer; for a suspect fit an "ok" one; and a median error
    up to the first's or the verdict's tolerance (3 times the scatter, at least 5 %)."""
    from modalid._fit_one import _refit_stands

    def report(verdict="ok", error=0.02, noise=0.01, missed=(), driving=True, n_modes=4,
               masses=None):
        masses = [1.0] * n_modes if masses is None else masses
        modes = pd.DataFrame({"frequency_hz": 10.0 * np.arange(1, n_modes + 1),
                              "modal_mass": masses})
        return {"verdict": verdict, "frf_median_relative_error": error,
                "noise_median_relative": noise, "missed_resonances_hz": list(missed),
                "driving_point": driving, "modes": modes}

    first = report(verdict="suspect", error=0.02, missed=[1.0])
    assert not _refit_stands(first, None, trigger="missed")
    assert not _refit_stands(first, report(verdict="failed"), trigger="missed")
    assert _refit_stands(first, report(error=0.04), trigger="missed")      # under 5 %
    assert not _refit_stands(first, report(error=0.06), trigger="missed")
    assert not _refit_stands(first, report(error=0.01, missed=[2.0]), trigger="missed")
    assert _refit_stands(first, report(error=0.04), trigger="failed")
    assert _refit_stands(first, report(error=0.04), trigger="stalled")
    assert not _refit_stands(first, report(error=0.06), trigger="stalled")
    assert not _refit_stands(first, report(error=0.01, driving=False), trigger="stalled")
    assert not _refit_stands(first, report(error=0.01, n_modes=3, missed=[1.0]),
                             trigger="stalled")
    # fewer modes, fewer missed: it stands if the first's strong positive modes are kept
    # (here the first's fourth, at 40 Hz, is lost: a real mode at the band's edge, which
    # no resonance test counts, was dropped this way)
    assert not _refit_stands(first, report(error=0.01, n_modes=3), trigger="stalled")
    weak = report(verdict="suspect", error=0.02, missed=[1.0], masses=[1.0, 1.0, 1.0, 50.0])
    assert _refit_stands(weak, report(error=0.01, n_modes=3), trigger="stalled")  # 1 -> 0
    assert not _refit_stands(first, report(verdict="suspect", error=0.01), trigger="suspect")
    assert _refit_stands(first, report(error=0.04), trigger="suspect")
    noisy = report(verdict="failed", error=0.5, noise=0.6)                  # tolerance 180 %
    assert _refit_stands(noisy, report(verdict="suspect", error=0.52), trigger="failed")
