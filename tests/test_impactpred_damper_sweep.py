"""impactpred.damper.sweep: parallel design sweeps, their errors, and the optimum clearance.

The parallel plumbing (executors, chunking, ordering, error naming, progress) is tested on a
small duck-typed damper defined here (the sweep may use only ImpactDamper's public API, so
any object with ``replace``/``simulate``/``primary_mass``/``excitation``/``contact`` is a
legitimate stand-in); the tests at the end run the real ImpactDamper when it is present.
"""

from __future__ import annotations

import dataclasses
import io
from concurrent.futures import Executor, Future, ThreadPoolExecutor

import matplotlib
import numpy as np
import pandas as pd
import pytest

matplotlib.use("Agg")

from impactpred import LinearSpring, Rigid  # noqa: E402
from impactpred.damper.sweep import (  # noqa: E402
    RESULT_COLUMNS,
    SweepError,
    _progress,
    optimum_clearance,
    plot_optimum_clearance,
    sweep,
)


# ------------------------------------------------------------------- a duck-typed damper
@dataclasses.dataclass(frozen=True)
class FakeForce:
    amplitude: float
    freq_hz: float
    phase: float = 0.0


@dataclasses.dataclass(frozen=True)
class FakeResult:
    primary_amplitude: float
    reduction: float
    impacts_per_cycle: float
    power_dissipated: float
    is_steady: bool
    steady_state_cycle: int | None
    amplitude_without_damper: float
    big: np.ndarray  # a whole time history: must never be shipped back by the sweep


@dataclasses.dataclass(frozen=True)
class FakeDamper:
    """Amplitude minimal at ``clearance = 1e-3 * freq_hz / 10``; raises at ``fail_clearance``."""

    damper_mass: float = 0.05
    clearance: float = 1e-3
    contact: object = Rigid()
    excitation: FakeForce = FakeForce(1.0, 10.0)
    primary_mass: float = 1.0
    fail_clearance: float = -1.0

    def replace(self, **changes):
        if changes.get("damper_mass", 0.0) > 0.5:
            raise ValueError("damper_mass must be <= 0.5 in this fake")
        return dataclasses.replace(self, **changes)

    def engine(self):
        """No phases to build (a sweep builds each design's engine before any run)."""
        return None

    def simulate(self, n_cycles, *, initial=None, samples_per_cycle=32, progress=False):
        if self.clearance == self.fail_clearance:
            raise FloatingPointError(f"engine blew up at clearance {self.clearance}")
        f = self.excitation.freq_hz
        stiffness = getattr(self.contact, "stiffness", 0.0)
        best = 1e-3 * f / 10.0
        amp = 1e-3 * (1.0 + ((self.clearance - best) / best) ** 2) * (1 + self.damper_mass)
        amp += 1e-12 * stiffness + 1e-9 * n_cycles
        steady = f < 11.0
        return FakeResult(amp, amp / 2e-3, 2.0 + self.clearance, 0.1 * f, steady,
                          3 if steady else None, 2e-3, np.zeros(100_000))


def direct(damper, n_cycles=20, **changes):
    res = damper.replace(**changes).simulate(n_cycles)
    return (res.primary_amplitude, res.reduction, res.impacts_per_cycle,
            res.power_dissipated, res.is_steady, res.steady_state_cycle,
            res.amplitude_without_damper)


def check_rows(table, damper, n_cycles=20):
    for _, row in table.iterrows():
        changes = {}
        if "freq_hz" in table:
            changes["excitation"] = dataclasses.replace(damper.excitation,
                                                        freq_hz=row["freq_hz"])
        if "mass_ratio" in table:
            changes["damper_mass"] = row["mass_ratio"] * damper.primary_mass
        if "clearance" in table:
            changes["clearance"] = row["clearance"]
        if "contact_stiffness" in table:
            changes["contact"] = dataclasses.replace(damper.contact,
                                                     stiffness=row["contact_stiffness"])
        expected = direct(damper, n_cycles, **changes)
        got = tuple(row[c] for c in RESULT_COLUMNS)
        for g, e in zip(got, expected):
            if e is None:
                assert pd.isna(g)
            else:
                assert g == e


# ------------------------------------------------------------------------- the plumbing
def test_thread_pool_2x2_every_row_in_grid_order_equals_direct_simulate():
    damper = FakeDamper()
    freqs, clearances = [9.0, 12.0], [5e-4, 1e-3]
    with ThreadPoolExecutor(2) as pool:
        table = sweep(damper, freq_hz=freqs, clearance=clearances, n_cycles=20,
                      executor=pool, progress=False, chunksize=1)
    assert list(table.columns) == ["freq_hz", "clearance", *RESULT_COLUMNS]
    assert len(table) == 4
    assert list(zip(table["freq_hz"], table["clearance"])) == [
        (9.0, 5e-4), (9.0, 1e-3), (12.0, 5e-4), (12.0, 1e-3)]
    check_rows(table, damper)
    assert table["is_steady"].dtype == bool
    assert table["steady_state_cycle"].isna().tolist() == [False, False, True, True]
    assert table.attrs["n_cycles"] == 20


def test_default_process_pool_2x2_and_all_four_axes():
    damper = FakeDamper(contact=LinearSpring(1e6))
    table = sweep(damper, freq_hz=[9.0, 12.0], clearance=np.array([5e-4, 1e-3]),
                  n_cycles=20, progress=False)
    assert len(table) == 4
    check_rows(table, damper)
    table = sweep(damper, freq_hz=[9.0, 12.0], mass_ratio=[0.02, 0.05], clearance=[1e-3],
                  contact_stiffness=[1e6, 1e7], n_cycles=20, progress=False)
    assert list(table.columns[:4]) == ["freq_hz", "mass_ratio", "clearance",
                                       "contact_stiffness"]
    assert len(table) == 8
    assert table["contact_stiffness"].tolist() == [1e6, 1e7] * 4
    check_rows(table, damper)


def test_chunking_keeps_order_for_any_chunk_size():
    damper = FakeDamper()
    freqs, clearances = np.linspace(8, 12, 5), np.geomspace(2e-4, 2e-3, 7)
    tables = []
    for chunksize in (None, 1, 3, 100):
        with ThreadPoolExecutor(3) as pool:
            tables.append(sweep(damper, freq_hz=freqs, clearance=clearances, n_cycles=20,
                                executor=pool, progress=False, chunksize=chunksize))
    for table in tables[1:]:
        pd.testing.assert_frame_equal(table, tables[0])
    check_rows(tables[0], damper)


def test_failing_combination_raises_naming_it_with_the_cause_chained():
    damper = FakeDamper(fail_clearance=1e-3)
    with ThreadPoolExecutor(2) as pool, \
            pytest.raises(SweepError, match=r"freq_hz=12, clearance=0\.001") as info:
        sweep(damper, freq_hz=[12.0], clearance=[5e-4, 1e-3], n_cycles=20, executor=pool,
              progress=False)
    assert isinstance(info.value, RuntimeError)
    assert isinstance(info.value.__cause__, FloatingPointError)
    assert info.value.combination == {"freq_hz": 12.0, "clearance": 1e-3}


def test_failing_combination_in_a_process_pool_keeps_the_worker_traceback():
    damper = FakeDamper(fail_clearance=5e-4)
    with pytest.raises(SweepError, match=r"clearance=0\.0005 failed") as info:
        sweep(damper, clearance=[1e-3, 5e-4, 2e-3], n_cycles=20, progress=False)
    cause = info.value.__cause__
    assert isinstance(cause, FloatingPointError)
    assert "traceback in the worker" in "".join(getattr(cause, "__notes__", []))


def test_combination_that_replace_refuses_is_named_before_any_task_runs():
    with pytest.raises(SweepError, match=r"mass_ratio=0\.9, clearance=0\.001 is invalid") as info:
        sweep(FakeDamper(), mass_ratio=[0.1, 0.9], clearance=[1e-3], n_cycles=20,
              executor=BrokenExecutor(), progress=False)
    assert isinstance(info.value.__cause__, ValueError)


class BrokenExecutor(Executor):
    """An executor that fails every task it is given (a lost worker, say)."""

    def submit(self, fn, /, *args, **kwargs):
        future = Future()
        future.set_exception(ConnectionError("worker lost"))
        return future


def test_executor_failing_a_task_raises_naming_its_combinations():
    with pytest.raises(SweepError, match=r"executor failed the task.*freq_hz=(9|10),") as info:
        sweep(FakeDamper(), freq_hz=[9.0, 10.0], clearance=[1e-3], n_cycles=20,
              executor=BrokenExecutor(), progress=False, chunksize=1)
    assert isinstance(info.value.__cause__, ConnectionError)


@pytest.mark.parametrize("kwargs, match", [
    ({"freq_hz": [10.0, np.nan]}, "freq_hz must be finite, got nan"),
    ({"freq_hz": [10.0, np.inf]}, "freq_hz must be finite, got inf"),
    ({"freq_hz": [10.0, -1.0]}, r"freq_hz must be > 0, got -1\.0"),
    ({"mass_ratio": [0.0]}, r"mass_ratio must be > 0, got 0\.0"),
    ({"clearance": [1e-3, -1e-4]}, r"clearance must be >= 0.*-0\.0001"),
    ({"clearance": []}, "clearance must not be empty"),
    ({"clearance": [[1e-3, 2e-3]]}, "clearance must be a 1-D"),
    ({}, "at least one axis"),
    ({"contact_stiffness": [1e6]}, "contact_stiffness can only be swept"),
    ({"clearance": [1e-3], "n_cycles": 0}, "n_cycles must be >= 1"),
])
def test_bad_axes_raise_value_error_naming_the_value(kwargs, match):
    with pytest.raises(ValueError, match=match):
        sweep(FakeDamper(), progress=False, **kwargs)


@pytest.mark.parametrize("value", ["fast", [1.0, "a"], [True, False], [1 + 2j]])
def test_non_numeric_axis_raises_type_error(value):
    with pytest.raises(TypeError, match="freq_hz must be a 1-D sequence"):
        sweep(FakeDamper(), freq_hz=value, progress=False)


def test_bad_executor_type():
    with pytest.raises(TypeError, match="executor"):
        sweep(FakeDamper(), clearance=[1e-3], executor="processes", progress=False)


def test_scalar_axis_is_one_value():
    with ThreadPoolExecutor(1) as pool:
        table = sweep(FakeDamper(), clearance=1e-3, n_cycles=20, executor=pool,
                      progress=False)
    assert table["clearance"].tolist() == [1e-3]


def test_progress_bar_reaches_the_total_on_stderr(capsys):
    with ThreadPoolExecutor(2) as pool:
        sweep(FakeDamper(), freq_hz=[9.0, 10.0], clearance=[1e-3, 2e-3], n_cycles=20,
              executor=pool, progress=True, chunksize=1)
    err = capsys.readouterr().err
    assert "4/4 combinations" in err
    with ThreadPoolExecutor(2) as pool:
        sweep(FakeDamper(), clearance=[1e-3, 2e-3], n_cycles=20, executor=pool,
              progress=False)
    assert capsys.readouterr().err == ""


def test_progress_bar_redraws_in_place_on_a_terminal():
    class Tty(io.StringIO):
        def isatty(self):
            return True

    stream = Tty()
    bar = _progress(3, True, stream)
    bar.mininterval = 0.0                       # redraw at every update (tqdm's rate limit)
    for _ in range(3):
        bar.update(1)
    bar.close()
    text = stream.getvalue()
    # tqdm redraws the one line with carriage returns, once per update, then ends it
    assert text.count("\r") >= 3 and "3/3 combinations" in text
    assert text.endswith("\n") and text.count("\n") == 1
    quiet = Tty()
    bar = _progress(3, False, quiet)
    bar.update(3)
    bar.close()
    assert quiet.getvalue() == ""


# ------------------------------------------------------------------------------ optimum
def test_optimum_clearance_and_plot_return_axes():
    damper = FakeDamper()
    freqs = [8.0, 10.0, 12.0]
    clearances = np.linspace(4e-4, 1.6e-3, 13)   # 0.1 mm steps: the optimum is on the grid
    with ThreadPoolExecutor(2) as pool:
        table = sweep(damper, freq_hz=freqs, clearance=clearances, n_cycles=20,
                      executor=pool, progress=False)
    best = optimum_clearance(table)
    np.testing.assert_allclose(best["clearance"], [8e-4, 1e-3, 1.2e-3], rtol=1e-9)
    assert best["freq_hz"].tolist() == freqs
    assert not best["on_edge"].any()
    ax = plot_optimum_clearance(table)
    assert isinstance(ax, matplotlib.axes.Axes)
    np.testing.assert_allclose(ax.lines[0].get_ydata(), [0.8, 1.0, 1.2])
    import matplotlib.pyplot as plt

    _fig, given = plt.subplots()
    assert plot_optimum_clearance(table, ax=given) is given
    plt.close("all")


def test_optimum_against_mass_ratio_and_edge_flag():
    with ThreadPoolExecutor(2) as pool:
        table = sweep(FakeDamper(), mass_ratio=[0.02, 0.05], clearance=[2e-3, 3e-3],
                      n_cycles=20, executor=pool, progress=False)
    with pytest.warns(UserWarning, match="no clearance of the grid"):   # reduction 1.02
        best = optimum_clearance(table)
    assert best.columns[0] == "mass_ratio"
    assert best["on_edge"].all()          # 1 mm is below the grid: the edge is flagged
    assert not best["damper_helps"].any()
    with pytest.raises(ValueError, match="no axis besides clearance"):
        optimum_clearance(table[table["mass_ratio"] == 0.02])
    with pytest.raises(ValueError, match="x must be one of"):
        optimum_clearance(table, x="freq_hz")



def test_optimum_says_when_no_clearance_helps():
    # at 6 Hz impacts only raise the amplitude: the best is an impact-free clearance, where
    # the damper idles; reported as such (the idle range's edge), warned, and crossed out
    table = pd.DataFrame({
        "freq_hz": [6.0] * 4 + [10.0] * 4,
        "clearance": [1e-4, 2e-4, 4e-4, 8e-4] * 2,
        "primary_amplitude": [4.3e-4, 4.4e-4, 3.96e-4, 3.96e-4 - 1e-12,
                              2.2e-3, 6.7e-4, 2.1e-3, 6.3e-3],
        "reduction": [1.08, 1.11, 1.0, 1.0 - 3e-12, 0.35, 0.11, 0.33, 1.0],
        "impacts_per_cycle": [4.5, 3.0, 0.0, 0.0, 44.0, 2.0, 1.6, 0.0],
        "is_steady": [True] * 8})
    with pytest.warns(UserWarning, match=r"no clearance of the grid lowers .* at freq_hz=6 "
                                         r"the best clearance of the grid has no impacts"):
        best = optimum_clearance(table)
    assert best["damper_helps"].tolist() == [False, True]
    assert best["clearance"].tolist() == [4e-4, 2e-4]     # 6 Hz: where the idle range starts
    assert best["impacts_per_cycle"].tolist() == [0.0, 2.0]
    with pytest.warns(UserWarning, match="no clearance of the grid") as caught:
        ax = plot_optimum_clearance(table)
    assert caught[0].filename == __file__              # the warning points at the caller
    crosses = [line for line in ax.lines if line.get_marker() == "x"]
    assert len(crosses) == 1 and crosses[0].get_xdata().tolist() == [6.0]
    # every clearance impacts and raises the amplitude (a second axis named too); a best
    # row without impacts but with a lower amplitude (not steady) is kept as it is
    worse = table.assign(mass_ratio=0.1)
    worse.loc[worse["freq_hz"] == 6.0, "impacts_per_cycle"] = [4.5, 3.0, 1.0, 0.5]
    worse.loc[worse["freq_hz"] == 6.0, "reduction"] = [1.08, 1.11, 1.05, 1.02]
    with pytest.warns(UserWarning, match=r"at freq_hz=6, mass_ratio=0.1 every clearance of "
                                         r"the grid impacts and raises"):
        assert optimum_clearance(worse, x="freq_hz")["damper_helps"].tolist() == [False, True]
    odd = table.copy()
    odd.loc[2, ["primary_amplitude", "reduction"]] = [2e-4, 0.5]   # 0 impacts, lower
    with pytest.warns(UserWarning, match="no impacts"):
        assert optimum_clearance(odd)["clearance"].tolist()[0] == 4e-4
    import matplotlib.pyplot as plt

    plt.close("all")


# ------------------------------------------------------------- the real ImpactDamper
def real_damper(damping_ratio=0.02):
    from data_synth import SpringMass
    from impactpred.damper import HarmonicForce, ImpactDamper, InstantaneousImpact

    primary = SpringMass(1.0, 4 * np.pi**2 * 100.0, damping_ratio=damping_ratio)  # 10 Hz
    return ImpactDamper(primary, damper_mass=0.05, clearance=5e-3,
                        contact=InstantaneousImpact(0.6),
                        excitation=HarmonicForce(1.0, 10.0))


def real_rows_equal_direct(table, damper, n_cycles):
    for _, row in table.iterrows():
        changes = {"excitation": damper.excitation.with_frequency(row["freq_hz"]),
                   "clearance": row["clearance"]}
        if "mass_ratio" in table:
            changes["damper_mass"] = row["mass_ratio"] * damper.primary_mass
        res = damper.replace(**changes).simulate(n_cycles)
        assert row["primary_amplitude"] == res.primary_amplitude
        assert row["reduction"] == res.reduction
        assert row["impacts_per_cycle"] == res.impacts_per_cycle
        assert row["power_dissipated"] == res.power_dissipated
        assert row["is_steady"] == res.is_steady
        assert row["amplitude_without_damper"] == res.amplitude_without_damper


@pytest.mark.parametrize("pool", ["threads", "processes"])
def test_real_damper_2x2_rows_equal_direct_simulate(pool):
    damper = real_damper()
    executor = ThreadPoolExecutor(2) if pool == "threads" else None
    try:
        table = sweep(damper, freq_hz=[9.0, 11.0], clearance=[3e-3, 6e-3], n_cycles=20,
                      executor=executor, progress=False)
    finally:
        if executor is not None:
            executor.shutdown()
    assert len(table) == 4 and table[["freq_hz", "clearance"]].notna().all().all()
    real_rows_equal_direct(table, damper, 20)


def test_real_damper_mass_ratio_axis_sets_the_damper_mass():
    damper = real_damper()
    with ThreadPoolExecutor(2) as pool:
        table = sweep(damper, freq_hz=[10.5], mass_ratio=[0.02, 0.1], clearance=[5e-3],
                      n_cycles=10, executor=pool, progress=False)
    real_rows_equal_direct(table, damper, 10)


def test_real_damper_failing_combination_names_it():
    """Undamped primary forced exactly at its natural frequency, which ``simulate`` refuses
    (no resonant-growth term in the closed form); a grid such as ``linspace(8, 12, 9)``
    holds 10.0 exactly. The sweep ran its tasks and failed mid-way, nothing stored; now
    the combination is named before any task runs (this executor fails every task), with
    the way out."""
    damper = real_damper(damping_ratio=0.0)
    with pytest.raises(SweepError, match=r"freq_hz=10, clearance=0\.005 is invalid: "
                                         r"ValueError: the excitation frequency 10\.0 Hz "
                                         r"coincides with an undamped mode .* move the "
                                         r"frequency off the mode") as info:
        sweep(damper, freq_hz=np.linspace(8, 12, 9), clearance=[5e-3], n_cycles=5,
              executor=BrokenExecutor(), progress=False)
    assert isinstance(info.value.__cause__, ValueError)
    assert info.value.combination == {"freq_hz": 10.0, "clearance": 5e-3}


def test_real_damper_contact_stiffness_refused_for_instantaneous_impact():
    with pytest.raises(ValueError, match="contact_stiffness can only be swept"):
        sweep(real_damper(), contact_stiffness=[1e6], progress=False)


def test_real_damper_with_a_modal_model_primary_in_the_default_process_pool():
    from data_synth import CantileverBeam
    from impactpred.damper import HarmonicForce, ImpactDamper, InstantaneousImpact

    primary = CantileverBeam(1.0, 0.056).modal_model(3, damping_ratio=0.02)
    damper = ImpactDamper(primary, damper_mass=0.0125, clearance=5e-3,
                          contact=InstantaneousImpact(0.6),
                          excitation=HarmonicForce(1.0, 10.0))
    table = sweep(damper, freq_hz=[9.0, 11.0], clearance=[3e-3, 6e-3], n_cycles=10,
                  progress=False)
    real_rows_equal_direct(table, damper, 10)
