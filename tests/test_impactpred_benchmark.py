"""The synthetic-hammer benchmark (impactpred.benchmark): table, exact references, pipeline."""

import math

import numpy as np
import pytest

from impactpred.benchmark import (
    TARGETS,
    Measurement,
    benchmark_cases,
    body_seed,
    check_targets,
    exact_reference,
    fit_max_order,
    markdown_table,
    measure_body,
    run_benchmark,
    targets_at,
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


def test_richardson_reference_extrapolates_the_convolution_to_dt_0():
    """The mass on a fixed rod by convolution at 1/200 s: its peak is 0.48 % low (first
    order in dt; five times the automatic step, which the plain run warns of);
    extrapolated from 1/200 and 1/400 s, within 0.005 % of the closed form (no warning:
    the extrapolation takes the first-order error out)."""
    import dataclasses

    case = _case("mass-rod M/m=1")
    exact = exact_reference(case).figures
    with pytest.warns(RuntimeWarning, match=r"dt=0.005 s is 5 times the step that resolves"):
        plain = exact_reference(dataclasses.replace(
            case, reference="convolution", dt_exact=1 / 200, richardson=False)).figures
    extrapolated = exact_reference(dataclasses.replace(
        case, reference="convolution", dt_exact=1 / 200, richardson=True)).figures
    assert plain["peak_force"] == pytest.approx(exact["peak_force"] * (1 - 0.0048), rel=2e-4)
    for k in ("peak_force", "impulse", "restitution"):
        assert extrapolated[k] == pytest.approx(exact[k], rel=5e-5)
    assert _case("ball-cantilever Hertz").richardson


@pytest.mark.parametrize("law", ["spring", "hertz"])
def test_compliant_reference_duration_is_not_held_to_the_grid(law):
    """Two unit masses, 1 m/s apart, under a compliant contact: the duration is closed form
    (``pi sqrt(mu / k)``, :func:`hertz_duration`). At a step of ``T / 300.5`` (about three
    times the automatic step: the plain run warns of it) the grid's duration is off by
    half a step (0.17 %); where the gap crosses zero, extrapolated from the step and its
    half, within 2e-5."""
    import dataclasses

    from data_synth import LumpedMass
    from impactpred._benchmark_cases import Case
    from impactpred.contact import Hertz, LinearSpring
    from impactpred.engine.hertz import hertz_duration

    contact, exact = ((LinearSpring(1e4), math.pi * math.sqrt(0.5 / 1e4)) if law == "spring"
                      else (Hertz(1e9), hertz_duration(1e9, 1.5, 0.5, 1.0)))
    case = Case("masses", "masses", "", LumpedMass(1.0), LumpedMass(1.0), 1.0, 0.0,
                2.0 * exact, "convolution", dt_exact=exact / 300.5, richardson=True,
                contact=contact)
    with pytest.warns(RuntimeWarning, match=r"times the step that resolves these bodies"):
        on_grid = exact_reference(dataclasses.replace(case, richardson=False))
    assert abs(on_grid.figures["contact_duration"] / exact - 1.0) > 1e-3
    crossing = exact_reference(case)
    assert crossing.figures["contact_duration"] == pytest.approx(exact, rel=2e-5)
    assert "gap crosses zero" in crossing.how


def test_gap_crossing_duration_finds_a_closing_between_samples():
    """The same masses and spring from a gap of 1.07 mm: the convolution interval starts
    on a sample whose gap is still open (the closing lies after it); the duration from the
    crossings at T / 300.5 and its half, extrapolated, is within 2e-5 of the closed form
    (it had kept the grid's start: 1.6e-3 off)."""
    from data_synth import LumpedMass
    from impactpred import Body, LinearSpring, solve_impact
    from impactpred._benchmark_cases import gap_crossing_duration

    exact = math.pi * math.sqrt(0.5 / 1e4)
    durations = [gap_crossing_duration(solve_impact(
        Body(LumpedMass(1.0), velocity=1.0), Body(LumpedMass(1.0)), contact=LinearSpring(1e4),
        gap=1.07e-3, t_end=2 * exact, dt=dt, method="convolution"))
        for dt in (exact / 300.5, exact / 601)]
    assert 2 * durations[1] - durations[0] == pytest.approx(exact, rel=2e-5)


def test_a_dashpot_reference_keeps_the_grids_duration():
    """A dashpot ends the force while the gap is still closed: the gap's crossing is not the
    contact's end (it gave +34 % with c = 60 N s/m), so the grid's duration is kept."""
    import dataclasses

    from data_synth import LumpedMass
    from impactpred._benchmark_cases import Case
    from impactpred.contact import LinearSpring

    case = Case("masses", "masses", "", LumpedMass(1.0), LumpedMass(3.0), 1.5, 0.0, 0.05,
                "convolution", dt_exact=1e-5, richardson=True,
                contact=LinearSpring(4e4, damping=60.0))
    reference = exact_reference(case)
    assert reference.how.endswith("(duration: the finer)")
    grid = exact_reference(dataclasses.replace(case, dt_exact=5e-6, richardson=False))
    assert reference.figures["contact_duration"] == grid.figures["contact_duration"]


def test_cases_are_defined():
    keys = [c.key for c in benchmark_cases()]
    assert "mass-rod M/m=1" in keys and "rod-rod L2/L1=1" in keys
    assert any("Hertz" in k for k in keys) and "rod-cantilever" in keys
    assert all(c.velocity1 > c.velocity2 for c in benchmark_cases())


def test_quick_subset_table():
    table = run_benchmark(cases=("mass-rod M/m=1",), quick=True, progress=False,
                          band_modes=(), workers=1)
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
    # one configuration without a band: its accuracy row, and e <= 1
    assert list(targets.result) == ["PASS", "PASS"]
    assert targets.target[0].startswith("10 modes, 1 %") and "1/1/2/10" in targets.target[0]
    assert "mass-rod M/m=1" in markdown_table(table)


def test_targets_are_marked_per_configuration():
    """Every (band, noise) gets its accuracy row (the issue's 1 % or 5 % targets) and its
    band row (all four figures held in >= 9 of 10 cases); a NaN error misses."""
    import pandas as pd

    def row(case, n, noise, err, held=True):
        r = {"case": case, "family": "rod-rod", "n_modes": n, "noise": noise,
             "e_pred": 0.9, "e_above_1": False}
        for k in ("e", "impulse", "duration", "peak"):
            r[f"{k}_err_%"] = err
            r[f"in_band_{k}"] = held
        return r

    rows = [row(f"c{i}", 10, 0.01, 0.5) for i in range(10)]
    rows += [row(f"c{i}", 10, 0.05, 1.5, held=i > 0) for i in range(10)]
    rows += [row(f"c{i}", 40, 0.05, 1.5 if i else math.nan, held=i > 1) for i in range(10)]
    targets = check_targets(pd.DataFrame(rows))
    assert len(targets) == 2 * 3 + 1
    got = dict(zip(targets.target, targets.result))
    assert got["10 modes, 1 %: every case within 1/1/2/10 % (e/J/D/P)"] == "PASS"
    assert got["10 modes, 5 %: every case within 2/2/4/20 % (e/J/D/P)"] == "PASS"
    assert got["40 modes, 5 %: every case within 2/2/4/20 % (e/J/D/P)"] == "MISS"
    assert got["10 modes, 5 %: band holds all four exact figures in >= 9 of 10 cases"] == "PASS"
    assert got["40 modes, 5 %: band holds all four exact figures in >= 9 of 10 cases"] == "MISS"
    assert targets_at(0.01) == TARGETS and targets_at(0.05)["peak_force"] == 20.0


def test_seeds_differ_by_run_and_wide_bands_get_a_higher_order():
    from data_synth import Rod

    rod = Rod(1.0, 1.0)
    seeds = {body_seed(rod, n, noise, run) for n in (10, 20, 40) for noise in (0.01, 0.05)
             for run in range(30)}
    assert len(seeds) == 3 * 2 * 30
    assert fit_max_order(10) is None and fit_max_order(26) is None
    assert fit_max_order(40) == 176
    # a band fitted by segments (8000 lines or more) keeps ModalFit's default order
    assert fit_max_order(40, 7999) == 176 and fit_max_order(40, 22500) is None


def test_records_hold_five_periods_of_the_first_mode():
    """A beam's f_top/f1 grows like n^2: at 20 modes its record grows past 4000 lines to
    hold 5 periods of mode 1, which is then identified to 0.5 % (0.3 % with this seed;
    3.6 periods in 4000 lines: 1.4 % high)."""
    import numpy as np

    from data_synth import CantileverBeam

    beam = CantileverBeam(10.0, 4.0)
    ident = measure_body(beam, 20, 0.01, seed=body_seed(beam, 20, 0.01))
    w = np.sort(ident.truth.modes["omega_n"].to_numpy())
    f1 = w[w > 0][0] / (2 * math.pi)
    assert ident.duration * f1 == pytest.approx(Measurement().min_periods)
    assert ident.n_lines > 5000
    found = ident.fit.report_["modes"]["frequency_hz"].to_numpy()
    assert np.min(np.abs(found - f1)) < 5e-3 * f1


def test_measurement_noise_level_is_the_frf_noise():
    """With the defaults (noise relative to each record's RMS) a 1 % hammer test gives H1
    estimates with about 1 % error per line, and the fit recovers the free rod's mass."""
    from data_synth import Rod

    ident = measure_body(Rod(1.0, 1.0, support="free"), 5, 0.01, seed=3, exact_noise=True)
    assert Measurement().noise_reference == "rms"
    assert 0.004 < ident.frf_noise < 0.03
    assert abs(ident.fit.report_["rigid_mass"] - 1.0) < 0.02


def test_bands_wider_than_a_cases_widest_are_reported_as_not_run():
    """Case.max_modes: a wider band's rows are in the table as failures (not run), and its
    accuracy target misses; the narrower band runs as usual."""
    import dataclasses

    case = dataclasses.replace(_case("mass-rod M/m=1"), max_modes=5)
    table = run_benchmark(cases=(case,), bands=(5, 8), noises=(0.01,), band_modes=(),
                          progress=False, workers=1)
    assert list(table.n_modes) == [5, 8]
    assert table.failure.iloc[0] == "" and math.isfinite(table["e_err_%"].iloc[0])
    assert table.failure.iloc[1].startswith("not run") and math.isnan(table["e_err_%"].iloc[1])
    got = dict(zip(table.attrs["targets"].target, table.attrs["targets"].result))
    assert got["8 modes, 1 %: every case within 1/1/2/10 % (e/J/D/P)"] == "MISS"


def test_a_stuck_phase_too_stiff_for_the_event_search_is_refused():
    """A rigid contact whose stuck phase has an eigenvalue needing more than 2e7 search
    steps over t_end is refused at once (a failure row), not solved for hours; the rate is
    the one the exact solver's search resolves (its step pi / (8 rate))."""
    import math

    from impactpred import Body, solve_impact
    from impactpred.benchmark import _check_search_steps
    from modalid import ModalModel

    def bodies(flexibility):
        # a light mode at 3000 rad/s and a tiny flexibility: a stiff stuck phase
        rod = ModalModel.from_modes([3.0, 9.0, 3000.0], 0.0, [0.5, 0.5, 1e-4],
                                    flexibility=flexibility)
        return Body(ModalModel(inverse_mass=1.0), velocity=1.0), Body(rod)

    _check_search_steps(*bodies(1e-3), 8.0)
    with pytest.raises(ValueError, match="event-search steps"):
        _check_search_steps(*bodies(1e-11), 8.0)
    # the same rate as the solver's (a short run shows its search step)
    res = solve_impact(*bodies(1e-11), t_end=1e-3, dt=1e-5, method="laplace")
    step = float(res.notes[0].split("event search step ")[1].split(" s")[0])
    with pytest.raises(ValueError) as info:
        _check_search_steps(*bodies(1e-11), 8.0)
    rate = float(str(info.value).split("eigenvalue, ")[1].split(" rad/s")[0])
    assert step == pytest.approx(math.pi / (8 * rate), rel=1e-2)
    # residues with a real part (relative degree 1): the stuck phase's fastest
    # eigenvalue is real, -h(0+)/D = -2.1e8 rad/s, a transient the search takes apart
    stiff = ModalModel.from_modes([3.0, 9.0, 3000.0], 0.01, [0.5, 0.5, 1e-4],
                                  flexibility=1e-9)
    stiff = ModalModel(poles=stiff.poles, residues=np.asarray(stiff.residues) * (1 + 0.05j),
                       flexibility=1e-9)
    _check_search_steps(Body(ModalModel(inverse_mass=1.0), velocity=1.0), Body(stiff), 8.0)


def test_a_figure_the_prediction_does_not_reach_is_a_failure_row():
    """A prediction still in contact at t_end has no restitution: the row records the
    failure (a miss) with NaN errors instead of raising."""
    import dataclasses

    from impactpred.benchmark import run_case

    case = _case("mass-rod M/m=1")
    short = dataclasses.replace(case, t_end=1.0)        # the contact lasts about 2 s
    row, result = run_case(short, 5, 0.01, reference=exact_reference(case),
                           uncertainty=False)
    assert result is not None and result.restitution is None
    assert row["failure"] == "predict: no restitution by t_end"
    assert math.isnan(row["e_err_%"]) and math.isfinite(row["impulse_err_%"])
