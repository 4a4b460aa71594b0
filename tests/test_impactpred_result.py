"""``ImpactResult``'s success and message, and its documented fields."""

import dataclasses

import pytest

from data_synth import LumpedMass
from impactpred import Body, ImpactResult, solve_impact
from impactpred.result import EnergyAudit


def _result():
    return solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(LumpedMass(2.0)), t_end=0.1)


def test_an_audited_exact_result_succeeds():
    r = _result()
    assert r.energy_audit is not None and r.energy_audit.ok
    assert r.success and r.message == "ok"


def test_a_flagged_audit_fails_with_its_reasons_and_no_audit_is_said():
    r = _result()
    bad = EnergyAudit(before=1.0, after=2.0, dissipated=0.0, stored=0.0, load_work=0.0,
                      scale=1.0, tolerance=1e-9, reasons=("1 J created", "restitution 1.4"))
    flagged = dataclasses.replace(r, energy_audit=bad)
    assert not flagged.success
    assert flagged.message == "1 J created; restitution 1.4"
    bare = dataclasses.replace(r, energy_audit=None)
    assert bare.success and bare.message == "not audited"


@pytest.mark.parametrize("name", ["energy_by_body", "energy_audit", "dirac_impulses"])
def test_the_documented_fields_are_the_fields(name):
    assert name in {f.name for f in dataclasses.fields(ImpactResult)}
    assert f"    {name} :" in ImpactResult.__doc__


def test_no_restitution_while_the_contact_is_still_closed_at_t_end():
    # a 1 kg mass on a fixed rod of 1 kg: the first contact lasts 3.068 s (Saint-Venant)
    from data_synth import Rod

    def solve(t_end):
        return solve_impact(Body(LumpedMass(1.0), velocity=1.0),
                            Body(Rod(1.0, 1.0, support="fixed")), t_end=t_end)

    with pytest.warns(UserWarning, match="still closed at t_end = 2 s"):
        open_ = solve(2.0)
    assert any("a longer t_end" in note for note in open_.notes)
    assert open_.in_contact_at_end and open_.contact_intervals[-1][1] == pytest.approx(2.0)
    assert open_.restitution is None and open_.restitution_first is None
    closed = solve(3.5)
    assert not closed.in_contact_at_end
    assert closed.contact_intervals[0][1] == pytest.approx(3.068, abs=2e-3)
    assert 0.6 < closed.restitution < 0.75


@pytest.mark.parametrize("how", ["pickle", "deepcopy", "copy"])
def test_results_stay_read_only_when_pickled_or_copied(how):
    """Unpickling does not run ``__post_init__``, which froze the arrays: a result sent
    through a process pool came back writeable, and ``r.force[:] = 0`` made its peak
    force 0 beside an unchanged impulse (walkthrough). Results, their point responses,
    bodies, sampled responses and damper results keep read-only arrays; ``==`` is
    identity (comparing the arrays had raised "truth value ... is ambiguous")."""
    import copy
    import pickle

    import numpy as np

    from data_synth import Rod, SpringMass
    from impactpred import ImpactDamper, InstantaneousImpact, SampledResponse
    from impactpred.damper import HarmonicForce

    again = {"pickle": lambda o: pickle.loads(pickle.dumps(o)), "deepcopy": copy.deepcopy,
             "copy": copy.copy}[how]
    rod = Rod(1.0, 1.0, support="fixed")
    result = solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(rod, outputs=[0.5]),
                          t_end=1.0)
    t = np.linspace(0.0, 2.0, 2001)
    damper = ImpactDamper(SpringMass(1.0, (2 * np.pi * 5) ** 2), damper_mass=0.1,
                          clearance=2e-3, contact=InstantaneousImpact(0.6),
                          excitation=HarmonicForce(5.0, 5.7)).simulate(3, samples_per_cycle=20)
    objects = {result: ("t", "force", "gap"), result.points[1]: ("t", "displacement"),
               Body(SpringMass(1.0, 1e4), vibration=[[0.0, 1.0]]): ("vibration",),
               SampledResponse(t, rod.impulse_response(t)): ("t", "impulse_response"),
               damper: ("t", "force", "primary")}
    for obj, names in objects.items():
        twin = again(obj)
        for name in names:
            with pytest.raises(ValueError, match="read-only"):
                getattr(twin, name)[0] = 1.0
        assert twin == twin and (twin == obj) is (twin is obj)
        hash(twin)
    # the repr names an array's shape, not its thousands of values
    assert "t=<array " in repr(result) and len(repr(result)) < 2000
