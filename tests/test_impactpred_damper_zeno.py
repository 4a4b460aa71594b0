"""Accumulations of instantaneous impacts (Zeno sequences) in the impact-damper engine.

With restitution ``e < 1`` a damper mass pushed onto a stop by a relative acceleration
``a`` bounces with approach velocities ``v_j = e^j v_0`` at intervals ``2 e v_j / a``,
which accumulate at ``t_inf = t_0 + 2 e v_0 / (a (1 - e))``; the engine closes the
sequence into the Rigid law's sticking (``impactpred.engine.cycle_loop.zeno_closes``). At
zero clearance the two stops coincide and every impact is plastic, so the damper mass moves
with the primary: a spring-mass primary then responds as the same spring-mass with the damper
mass added, in closed form. The tests with the ``loop`` fixture run both the compiled
loop and the Python loop.
"""

import math

import numpy as np
import oracle_event_search
import pytest

from data_synth import SpringMass
from impactpred import Rigid
from impactpred.damper import HarmonicForce, ImpactDamper, InstantaneousImpact
from impactpred.engine import cycle_compiled as compiled
from impactpred.engine import cycle_run as engine_run

M, K, ZETA, MD, F0, FREQ = 1.0, (2 * np.pi * 5) ** 2, 0.02, 0.1, 5.0, 4.5
C_VISC = 2 * ZETA * math.sqrt(K * M)        # the primary's viscous damping (N s/m)


@pytest.fixture(params=[True, False], ids=["compiled", "python"])
def loop(request, monkeypatch):
    monkeypatch.setattr(engine_run, "_COMPILED", request.param)
    if not request.param:       # the Python loop with the Python search (the oracle)
        monkeypatch.setattr(engine_run, "_SEARCH", oracle_event_search.first_event)
    return request.param


def _forced(m, t, *, y0=0.0, v0=0.0):
    """Closed form of ``m y'' + C_VISC y' + K y = F0 cos(2 pi FREQ t)`` (m) from ``y0, v0``."""
    om = 2 * np.pi * FREQ
    amp = F0 / (K - m * om ** 2 + 1j * C_VISC * om)
    wn = math.sqrt(K / m)
    z = C_VISC / (2 * math.sqrt(K * m))
    wd = wn * math.sqrt(1 - z * z)
    a = y0 - amp.real
    b = (v0 - (1j * om * amp).real + z * wn * a) / wd
    return (amp * np.exp(1j * om * t)).real + np.exp(-z * wn * t) * (
        a * np.cos(wd * t) + b * np.sin(wd * t))


def _damper(clearance, contact):
    return ImpactDamper(SpringMass(M, K, damping_ratio=ZETA), damper_mass=MD,
                        clearance=clearance, contact=contact,
                        excitation=HarmonicForce(F0, FREQ))




@pytest.mark.parametrize("contact", [InstantaneousImpact(0.6), InstantaneousImpact(0.95),
                                     Rigid()], ids=repr)
def test_zero_clearance_moves_the_damper_mass_with_the_primary(contact, loop):
    r = _damper(0.0, contact).simulate(50)
    # one impact at the start, then a change of stop where the force changes sign: two
    # per cycle (the runaway made about a million per cycle)
    assert len(r.impacts) <= 2 * 50 + 2
    assert r.impacts_per_cycle == 2.0
    exact = _forced(M + MD, r.t)        # the primary with the damper mass added, from rest
    scale = np.max(np.abs(exact))
    assert np.max(np.abs(r.primary - exact)) < 1e-12 * scale
    assert np.max(np.abs(r.damper - exact)) < 1e-12 * scale


@pytest.mark.parametrize("e", [0.0, 0.6, 0.95])
def test_zero_clearance_impact_is_plastic_and_conserves_momentum(e, loop):
    # the damper mass starts at 0.3 m/s against the primary at rest: the impacts v, e v,
    # e^2 v, ... between the coincident stops happen at one instant and sum to a plastic
    # impact, after which the two move together with the momentum m_d v
    d = _damper(0.0, InstantaneousImpact(e))
    v_d = 0.3
    r = d.simulate(20, initial=d.initial_state(damper_velocity=v_d))
    first = r.impacts.iloc[0]
    assert first["relative_velocity"] == pytest.approx(v_d, rel=1e-12)
    assert first["impulse"] == pytest.approx(v_d / (1 / MD + 1 / M), rel=1e-12)
    assert r.impacts_per_cycle == 2.0
    exact = _forced(M + MD, r.t, v0=MD * v_d / (M + MD))
    scale = np.max(np.abs(exact))
    assert np.max(np.abs(r.primary - exact)) < 1e-12 * scale
    assert np.max(np.abs(r.damper - exact)) < 1e-12 * scale


def test_vanishing_clearance_behaves_like_zero(loop):
    # vanishing: under what the event search resolves, 1e-12 of the motion's terms over a
    # forcing period (~5e-14 m of this 5 cm motion). 1e-12 m passed for vanishing while that
    # tolerance was weighted by the unit of time (1 s: 1.5e-12 m); resolved now, its
    # bounces are real chatter, 4 impacts a cycle before the Zeno rule closes them
    c = 1e-13
    r = _damper(c, InstantaneousImpact(0.6)).simulate(50)
    assert len(r.impacts) <= 2 * 50 + 10
    assert r.impacts_per_cycle == 2.0
    exact = _forced(M + MD, r.t)
    # the clearance's own effect is O(c) (the damper mass crosses 2 c at each change of
    # stop; Rigid at this clearance gives the same 1.3 c): a few c, ~1e-10 of the motion
    assert np.max(np.abs(r.primary - exact)) < 3 * c
    assert np.max(np.abs(r.damper - exact)) < 4 * c
    # the closed Zeno sequences add far less than the clearance itself
    rigid = _damper(c, Rigid()).simulate(50)
    on = r.grid_index >= 0
    assert np.max(np.abs(r.primary[on] - rigid.primary[rigid.grid_index >= 0])) < 0.05 * c


def test_bouncing_sequence_accumulates_at_the_geometric_series_limit(loop):
    # a soft (5 mHz), slowly forced (2.5 mHz) primary of 1 kg at rest under 1 N: over the
    # ~20 ms of the sequence its acceleration is a = F0/M = 1 m/s^2 to ~1e-7, a constant
    # "gravity" pulling the lower stop onto the damper mass, which starts at rest delta
    # above it; restitution e at every bounce
    e, delta, c, a = 0.6, 1e-5, 1e-2, 1.0
    d = ImpactDamper(SpringMass(1.0, (2 * np.pi * 5e-3) ** 2), damper_mass=0.01,
                     clearance=c, contact=InstantaneousImpact(e),
                     excitation=HarmonicForce(1.0, 2.5e-3))
    r = d.simulate(1, initial=d.initial_state(damper_displacement=-c + delta))
    imp = r.impacts
    k = int(np.argmax(imp["duration"].to_numpy() > 0))    # the impact that closes it
    seq = imp.iloc[:k + 1]
    assert np.all(seq["side"] == -1) and np.all(seq["duration"].iloc[:k] == 0.0)
    # a Zeno sequence is closed after at most ln(1e12) / (2 ln(1/e)) = 27 impacts
    assert 3 < k + 1 <= 27
    t0, v0 = math.sqrt(2 * delta / a), math.sqrt(2 * a * delta)
    t_inf = t0 + 2 * e * v0 / (a * (1 - e))
    j = np.arange(k + 1)
    series = t0 + 2 * e * v0 * (1 - e ** j) / (a * (1 - e))
    # the late bounces are near the gap's resolution: absolute tolerances
    np.testing.assert_allclose(seq["relative_velocity"], v0 * e ** j, rtol=0, atol=1e-6 * v0)
    np.testing.assert_allclose(seq["time"], series, rtol=0, atol=1e-6 * t_inf)
    # the rest of the sequence, closed, is the tail of the same series: sticking starts
    # where the bounces would have accumulated, less that tail (here ~1 % of t_inf)
    v_k = seq["relative_velocity"].iloc[k]
    tail = 2 * e * v_k / (a * (1 - e))
    assert seq["time"].iloc[k] + tail == pytest.approx(t_inf, rel=1e-6)
    assert 0 < tail < 0.02 * t_inf
    # and the damper mass then moves with the primary for tens of seconds (until the
    # contact force turns tensile)
    assert imp["duration"].iloc[k] > 10.0


def test_impacts_that_do_not_accumulate_raise_naming_the_cause(loop, monkeypatch):
    # elastic impacts between stops 2 nm apart: ~1.5e8 per second, never sticking
    monkeypatch.setattr(compiled, "MAX_IMPACTS_PER_PERIOD", 300)
    d = _damper(1e-9, InstantaneousImpact(1.0))
    with pytest.raises(RuntimeError, match=r"more than 300 impacts within one forcing "
                                           r"period .*restitution 1\.0, clearance 1e-09 m"):
        d.simulate(2, initial=d.initial_state(damper_velocity=0.3))
    # with e < 1 the same start ends in sticking: after ~25 impacts, then a few per
    # change of stop (the mass crosses the 2 nm and bounces a few times)
    d = _damper(1e-9, InstantaneousImpact(0.6))
    r = d.simulate(2, initial=d.initial_state(damper_velocity=0.3))
    assert len(r.impacts) < 100
    assert r.final_state.mode == "stuck"


def test_elastic_impact_between_coincident_stops_raises(loop):
    d = _damper(0.0, InstantaneousImpact(1.0))
    with pytest.raises(RuntimeError, match="restitution 1 an impact between stops that "
                                           "coincide to rounding"):
        d.simulate(1, initial=d.initial_state(damper_velocity=0.3))


def test_long_chunks_pause_to_draw_the_progress_bar_without_changing_the_run(capsys,
                                                                            monkeypatch):
    # 44 impacts per cycle: the 40 cycles (one chunk) take ~1,800 phases; pausing every
    # 100 of them redraws the bar inside the chunk, and a pause between two phases
    # changes nothing
    d = _damper(3e-3, InstantaneousImpact(0.6))
    whole = d.simulate(40)
    monkeypatch.setattr(compiled, "PHASES_PER_CALL", 100)
    paused = d.simulate(40, progress=True)
    err = capsys.readouterr().err
    shown = [int(part.split("/")[0]) for part in err.split("(")[1:]]
    assert shown[0] == 0 and shown[-1] == 40
    assert len([k for k in shown if 0 < k < 40]) >= 5
    np.testing.assert_array_equal(whole.t, paused.t)
    np.testing.assert_array_equal(whole.primary, paused.primary)
    np.testing.assert_array_equal(whole.impacts["time"], paused.impacts["time"])
