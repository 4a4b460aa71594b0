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
