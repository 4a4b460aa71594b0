"""The compiled event loop of the impact damper (Rigid / InstantaneousImpact contacts)
against the Python loop and the Python event search it replaces
(``impactpred.engine.cycle_run._COMPILED``, ``tests/oracle_event_search.py``).

The two run the same rules and differ only in rounding (loops instead of BLAS products,
Taylor sums on a phase's start grid). Where the motion is periodic they agree to
rounding over whole runs. Where it chatters (trains of micro-impacts on a truncated
beam, elastic impacts on an undamped-like primary) rounding differences grow by roughly
a factor 3 per impact, so histories are compared before they have grown past 1e-9; the
Python loop itself diverges the same way from a 1-ulp change of the force amplitude
(bench case, 100 cycles: the 46th contact differs, 1520 vs 1545 contacts, amplitude
12.21 vs 11.93 mm).
"""

import numpy as np
import oracle_event_search
import pytest

from data_synth import CantileverBeam, SpringMass
from impactpred import Rigid
from impactpred.damper import HarmonicForce, ImpactDamper, InstantaneousImpact
from impactpred.engine import cycle_compiled as compiled
from impactpred.engine import cycle_run as engine_run


def _both(damper, n_cycles, monkeypatch, **kwargs):
    fast = damper.simulate(n_cycles, **kwargs)
    with monkeypatch.context() as m:
        m.setattr(engine_run, "_COMPILED", False)
        m.setattr(engine_run, "_SEARCH", oracle_event_search.first_event)
        slow = damper.simulate(n_cycles, **kwargs)
    return fast, slow


def _assert_same_run(fast, slow, rtol, v_scale=None):
    """``v_scale`` (m/s): the scale of the relative velocities where they are far below
    the motion's (at a clearance of nanometres, or 0 to rounding at zero clearance)."""
    assert len(fast.impacts) == len(slow.impacts) > 0
    assert fast.t.size == slow.t.size
    np.testing.assert_array_equal(fast.grid_index, slow.grid_index)
    T = slow.period
    for col, scale in (("time", T), ("impulse", None), ("relative_velocity", v_scale),
                       ("duration", T)):
        a, b = fast.impacts[col].to_numpy(), slow.impacts[col].to_numpy()
        ref = scale if scale is not None else np.max(np.abs(b))
        assert np.max(np.abs(a - b)) <= rtol * ref, col
    np.testing.assert_array_equal(fast.impacts["side"], slow.impacts["side"])
    np.testing.assert_allclose(fast.t, slow.t, rtol=0, atol=rtol * T)
    for name in ("primary", "primary_velocity", "damper", "damper_velocity", "force",
                 "input_work"):
        a, b = getattr(fast, name), getattr(slow, name)
        # the contact force is 0 to rounding on most samples: scaled by the excitation's
        scale = np.max(np.abs(b)) if name != "force" else np.max(np.abs(slow.excitation))
        assert np.max(np.abs(a - b)) <= rtol * scale, name
    assert fast.final_state.mode == slow.final_state.mode


def _bench_beam():
    # benchmarks/bench_damper.py's case: 20-mode cantilever, f1 = 10 Hz, 1 % damping,
    # damper mass 5 % of the tip's modal mass, rigid stops at +-20 mm, 1 N at f1
    beam = CantileverBeam(1.0, 0.0559591)
    model = beam.modal_model(20, damping_ratio=0.01)
    f1 = float(model.modes["frequency_hz"].iloc[0])
    return ImpactDamper(model, damper_mass=0.0125, clearance=0.02, contact=Rigid(),
                        excitation=HarmonicForce(1.0, f1))


@pytest.mark.slow
def test_beam_matches_the_python_loop_until_the_chatter_amplifies_rounding(monkeypatch):
    d = _bench_beam()
    fast, slow = _both(d, 9, monkeypatch)       # the first macroscopic impacts (22 contacts)
    _assert_same_run(fast, slow, 1e-9)
    fast, slow = _both(d, 100, monkeypatch)
    a, b = fast.impacts["time"].to_numpy(), slow.impacts["time"].to_numpy()
    k = 40
    assert np.max(np.abs(a[:k] - b[:k])) < 1e-9 * d.engine().period
    # afterwards the same physics, not the same rounding. One run's statistics are one
    # draw of the chatter's: under 1-ulp changes of the force amplitude the impacts per
    # cycle at 100 cycles range over 14.9-16.7 (sd 0.6) in either loop, so single runs
    # differed by 11 % between loops and by 18 % between splits of the stuck phase.
    # Compared: the means over six such changes (their difference's sd ~2 %)
    ex = d.excitation
    runs = [_both(d.replace(excitation=HarmonicForce(ex.amplitude * (1 + 2.2e-16 * k_ulp),
                                                     ex.freq_hz)), 100, monkeypatch)
            for k_ulp in range(6)]
    fast_stats, slow_stats = (np.array([[r.impacts_per_cycle, r.primary_amplitude]
                                        for r in loop]) for loop in zip(*runs))
    np.testing.assert_allclose(fast_stats.mean(axis=0), slow_stats.mean(axis=0), rtol=0.08)


def test_the_general_split_of_the_stuck_phase_gives_the_same_periodic_run():
    """The stuck phases split by the general eigendecomposition (``Engine(rank_one=
    False)``, the default before) and by the rank-one route: a periodic run agrees to
    rounding (a rigid contact that sticks on both stops, 60 cycles)."""
    from impactpred.damper._engine import Engine

    K, F0 = (2 * np.pi) ** 2, 1.0
    d = ImpactDamper(SpringMass(1.0, K, damping_ratio=0.02), damper_mass=0.05,
                     clearance=2 * F0 / K, contact=Rigid(), excitation=HarmonicForce(F0, 1.3))
    rank_one = d.simulate(60, samples_per_cycle=64)
    assert d.engine().rank_one
    general = d.replace()
    object.__setattr__(general, "_engine_cache", Engine(
        general._model, damper_mass=general.damper_mass, clearance=general.clearance,
        contact=general.contact, excitation=general.excitation, base_spring=general._base,
        rank_one=False))
    _assert_same_run(rank_one, general.simulate(60, samples_per_cycle=64), 1e-10)
    assert (rank_one.impacts["duration"] > 0).any()          # its stuck phases ran


@pytest.mark.parametrize("contact, n_cycles", [(InstantaneousImpact(0.5), 100), (Rigid(), 60)])
def test_periodic_spring_mass_runs_match_the_python_loop(contact, n_cycles, monkeypatch):
    # two impacts per cycle (Masri-Caughey-like, damped): the runs agree to rounding
    K, F0 = (2 * np.pi) ** 2, 1.0
    d = ImpactDamper(SpringMass(1.0, K, damping_ratio=0.02), damper_mass=0.05,
                     clearance=2 * F0 / K, contact=contact, excitation=HarmonicForce(F0, 1.3))
    fast, slow = _both(d, n_cycles, monkeypatch, samples_per_cycle=64)
    _assert_same_run(fast, slow, 1e-11)


def test_elastic_impacts_match_the_python_loop_before_rounding_grows(monkeypatch):
    sm = SpringMass(1.0, (2 * np.pi * 5) ** 2, damping_ratio=0.05)
    d = ImpactDamper(sm, damper_mass=0.1, clearance=2e-3, contact=InstantaneousImpact(1.0),
                     excitation=HarmonicForce(5.0, 5.7))
    fast, slow = _both(d, 4, monkeypatch, samples_per_cycle=40)
    _assert_same_run(fast, slow, 1e-9)
    assert np.all(fast.impacts["duration"] == 0.0)


# restitution 0.6: at 0 every impact is plastic (the runs agree to rounding); at 1 nm
# bounces at each change of stop (531 impacts in 30 cycles: the event search's tolerance,
# scale-free, resolves more of them than the 443 it did in SI), whose chatter amplifies
# rounding as at 3 mm (1.1e-9 of the motion); at 3 mm ~44 impacts per cycle, most of them
# in Zeno sequences closed into sticking, whose chatter amplifies rounding as the beam's
# does (~1e-9: the loops' two compilations differ by that much). The same impacts and
# closing decisions throughout
@pytest.mark.parametrize("clearance, rtol", [(0.0, 1e-12), (1e-9, 1e-8), (3e-3, 1e-8)])
def test_zeno_sequences_match_the_python_loop(clearance, rtol, monkeypatch):
    sm = SpringMass(1.0, (2 * np.pi * 5) ** 2, damping_ratio=0.02)
    d = ImpactDamper(sm, damper_mass=0.1, clearance=clearance,
                     contact=InstantaneousImpact(0.6), excitation=HarmonicForce(5.0, 4.5))
    fast, slow = _both(d, 30, monkeypatch, samples_per_cycle=40)
    _assert_same_run(fast, slow, rtol, v_scale=np.max(np.abs(slow.primary_velocity)))


def test_chunks_give_the_run_itself_and_continuation_matches(monkeypatch):
    d = _bench_beam()
    whole = d.simulate(12)
    with monkeypatch.context() as m:
        m.setattr(compiled, "CHUNK_CYCLES", 1)
        chunked = d.simulate(12)
    np.testing.assert_array_equal(whole.t, chunked.t)
    np.testing.assert_array_equal(whole.primary, chunked.primary)
    np.testing.assert_array_equal(whole.impacts["time"], chunked.impacts["time"])
    # a run continued from inside a contact equals the Python loop's continuation
    first = d.simulate(10)
    for _ in range(200):            # on, a cycle at a time, to the end of one inside contact
        if first.final_state.mode == "stuck":
            break
        first = d.simulate(1, initial=first)
    assert first.final_state.mode == "stuck"
    fast, slow = _both(d, 1, monkeypatch, initial=first)
    assert fast.impacts["time"].iloc[0] == first.final_state.open_impact["time"]
    assert len(fast.impacts) > 5 and len(slow.impacts) > 5
    for col in ("time", "side", "impulse", "duration"):
        np.testing.assert_allclose(fast.impacts[col][:5], slow.impacts[col][:5], rtol=1e-9,
                                   err_msg=col)


def test_progress_bar_is_drawn_between_chunks(capsys, monkeypatch):
    from impactpred.engine import cycle_compiled as _engine_compiled

    # a chunk per 2 cycles; a chunk ends at the first event after its end, and the first
    # free flight (no impact yet) may run past several chunk ends at once
    monkeypatch.setattr(_engine_compiled, "CHUNK_CYCLES", 2)
    d = _bench_beam()
    d.simulate(40, progress=True)
    err = capsys.readouterr().err
    shown = [int(part.split("/")[0]) for part in err.split("(")[1:]]
    assert shown[0] == 0 and shown[-1] == 40 and "100% (40/40 cycles)" in err
    assert len([k for k in shown if 0 < k < 40]) >= 5       # drawn between chunks
