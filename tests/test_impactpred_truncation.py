"""continue_above_band: exact answers on the uniform fixed rod (G = T/m, e = 0.6989)."""

import numpy as np
import pytest

from data_synth import LumpedMass, Rod
from impactpred import Body, solve_impact
from impactpred.truncation import (continue_above_band, high_frequency_conductance,
                                   impact_figures)

EXACT_E = 0.698876  # mass M = m on a fixed rod, all contacts (reference_impacts)


def _band_top(n, T=1.0):
    """Midway between fixed-rod modes n and n+1 (Hz)."""
    return n / (2 * T)


@pytest.mark.parametrize("n", [10, 20])
@pytest.mark.parametrize("mass, T", [(1.0, 1.0), (2.5, 0.3)])
def test_conductance_is_the_rod_admittance(n, mass, T):
    model = Rod(mass, T, support="fixed").modal_model(n, residual=True)
    G, omega_top, dw, mk = high_frequency_conductance(model, _band_top(n, T))
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
