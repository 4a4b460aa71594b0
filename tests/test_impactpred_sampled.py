"""SampledResponse: a measured impulse response, and the drift of a free body's."""

import warnings

import numpy as np
import pytest

from data_synth import LumpedMass, SpringMass
from impactpred import Body, LinearSpring, SampledResponse, solve_impact


def test_a_free_bodys_drift_without_its_inverse_mass_is_warned_about():
    """A 2 kg free mass's impulse response ``t / 2``: without ``inverse_mass`` the restitution
    of a 1 kg mass striking it through a spring was booked as 0.33 (exact 1.0) with no
    word; the warning gives the slope, and with it the restitution is 1.0."""
    t = np.arange(0.0, 0.2, 1e-5)
    with pytest.warns(UserWarning, match=r"drifts at the record's end at 0.5 m/\(N s\^2\) .*"
                                         r"give inverse_mass=0.5"):
        bare = SampledResponse(t, t / 2.0)
    runs = dict(contact=LinearSpring(1e4), t_end=0.1)
    assert solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(bare),
                        **runs).restitution == pytest.approx(1 / 3, abs=0.01)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        given = SampledResponse(t, t / 2.0, inverse_mass=0.5)
    assert solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(given),
                        **runs).restitution == pytest.approx(1.0, abs=2e-3)


def test_a_grounded_bodys_decaying_response_is_not_a_drift():
    """A grounded spring-mass (10 Hz, zeta 2 %) over 20 periods, and a free one's
    vibration on its drift with the drift's inverse mass given: no warning."""
    t = np.arange(0.0, 2.0, 1e-4)
    wn, zeta = 2 * np.pi * 10.0, 0.02
    wd = wn * np.sqrt(1 - zeta ** 2)
    ringing = np.exp(-zeta * wn * t) * np.sin(wd * t) / wd
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        SampledResponse(t, ringing)                       # 1 kg: h = e^(-zeta wn t) sin / wd
        SampledResponse(t, t / 4.0 + ringing, inverse_mass=0.25)
    with pytest.warns(UserWarning, match="drifts"):       # the same vibration, free, bare
        SampledResponse(t, t / 4.0 + ringing)


def test_a_record_too_coarse_for_the_contact_says_so():
    """An undamped 1 kg / 1e4 N/m body known by its impulse response at 10 kHz, struck by
    1 kg at 1 m/s: the step is the record's. Through a 1e7 N/m spring the contact lasts
    10 samples and 45 % of the energy was lost (restitution 0.64 for 1.00) with no word;
    now a RuntimeWarning and a note give the step the contact needs. Through 1e3 N/m the
    record resolves it: nothing said, and the exact spring-mass's restitution to 0.2 %
    (0.9884 for 0.9906: the record's step response is its samples' trapezoidal sum)."""
    t = np.arange(0.0, 2.0, 1e-4)
    body = SampledResponse(t, np.sin(100.0 * t) / 100.0)
    with pytest.warns(RuntimeWarning, match=r"the step is the sampled record's, 0.0001 s: "
                                            r"\d+ times the step the contact"):
        coarse = solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(body),
                              contact=LinearSpring(1e7), t_end=0.5)
    assert coarse.restitution < 0.9                      # what it warns about
    assert any("does not resolve the contact" in n for n in coarse.notes)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        fine = solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(body),
                            contact=LinearSpring(1e3), t_end=0.5)
    exact = solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(SpringMass(1.0, 1e4)),
                         contact=LinearSpring(1e3), t_end=0.5)
    assert fine.restitution == pytest.approx(exact.restitution, abs=3e-3)
