"""The synthetic-hammer benchmark (impactpred.benchmark): table, exact references, pipeline."""

import math

import pytest

from impactpred.benchmark import (
    TARGETS,
    Measurement,
    benchmark_cases,
    check_targets,
    exact_reference,
    markdown_table,
    measure_body,
    run_benchmark,
)


def _case(key):
    return {c.key: c for c in benchmark_cases()}[key]


def test_exact_references():
    ref = exact_reference(_case("mass-rod M/m=1"))
    assert ref.figures["restitution"] == pytest.approx(0.6988755820, abs=1e-9)
    ref = exact_reference(_case("rod-rod L2/L1=1"))
    assert ref.figures["restitution"] == pytest.approx(1.0, abs=1e-12)
    assert ref.figures["contact_duration"] == pytest.approx(2.0)
    assert ref.figures["impulse"] == pytest.approx(1.0 * 1.0 * 2.0 / 2.0 * 2.0)  # m1m2/M v12 2T/T
    assert ref.figures["peak_force"] == pytest.approx(1.0)


def test_cases_are_defined():
    keys = [c.key for c in benchmark_cases()]
    assert "mass-rod M/m=1" in keys and "rod-rod L2/L1=1" in keys
    assert any("Hertz" in k for k in keys) and "rod-cantilever" in keys
    assert all(c.velocity1 > c.velocity2 for c in benchmark_cases())


def test_quick_subset_table():
    table = run_benchmark(cases=("mass-rod M/m=1",), quick=True, progress=False,
                          band_modes=())
    assert len(table) == 1
    for col in ("duration_err_%", "peak_err_%", "impulse_err_%", "e_err_%", "force_err_%",
                "e_truth_err_%", "t_identify_s", "t_predict_s", "in_band_e", "e_above_1"):
        assert col in table.columns
    row = table.iloc[0]
    assert row.failure == ""
    for col in ("duration_err_%", "peak_err_%", "impulse_err_%", "e_err_%", "force_err_%"):
        assert math.isfinite(row[col])
    # the targets at 10 modes and 1 % noise
    assert abs(row["e_err_%"]) < 1 and abs(row["impulse_err_%"]) < 1
    assert abs(row["duration_err_%"]) < 2 and abs(row["peak_err_%"]) < 10
    assert row.e_exact == pytest.approx(0.6988755820, abs=1e-9)
    targets = check_targets(table)
    assert set(targets.result) <= {"PASS", "MISS", "info"} and len(targets) == len(TARGETS) + 3
    assert "mass-rod M/m=1" in markdown_table(table)


def test_measurement_noise_level_is_the_frf_noise():
    """With the defaults (noise relative to each record's RMS) a 1 % hammer test gives H1
    estimates with about 1 % error per line, and the fit recovers the free rod's mass."""
    from data_synth import Rod

    ident = measure_body(Rod(1.0, 1.0, support="free"), 5, 0.01, seed=3)
    assert Measurement().noise_reference == "rms"
    assert 0.004 < ident.frf_noise < 0.03
    assert abs(ident.fit.report_["rigid_mass"] - 1.0) < 0.02
