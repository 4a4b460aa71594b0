"""impactpred.damper.sweep(store=...): rows written as they finish, a killed or failed sweep
resumed with 0 combinations lost and 0 run twice, the table identical to an uninterrupted
run; the store's format and its refusals (impactpred.damper._sweep_store)."""

from __future__ import annotations

import dataclasses
import importlib.util
import os
import signal
import subprocess
import sys
import textwrap
from concurrent.futures import ThreadPoolExecutor

import pandas as pd
import pytest

from impactpred.damper.sweep import RESULT_COLUMNS, SweepError, sweep

# a duck-typed damper (the sweep uses only ImpactDamper's public API) that logs every run it
# starts to $SWEEP_LOG and kills its own process with SIGKILL at the $SWEEP_KILL_AT-th run
SCRIPT = textwrap.dedent('''
    import dataclasses, math, os, pickle, signal, sys, time
    from concurrent.futures import ThreadPoolExecutor

    @dataclasses.dataclass(frozen=True)
    class Force:
        amplitude: float
        freq_hz: float
        phase: float = 0.0

    @dataclasses.dataclass(frozen=True)
    class Result:
        primary_amplitude: float
        reduction: float
        impacts_per_cycle: float
        power_dissipated: float
        is_steady: bool
        steady_state_cycle: object
        amplitude_without_damper: float

    @dataclasses.dataclass(frozen=True)
    class Damper:
        damper_mass: float = 0.05
        clearance: float = 1e-3
        contact: object = None
        excitation: Force = Force(1.0, 10.0)
        primary_mass: float = 1.0

        def replace(self, **changes):
            return dataclasses.replace(self, **changes)

        def engine(self):
            return None

        def simulate(self, n_cycles, **kwargs):
            f, c = self.excitation.freq_hz, self.clearance
            log = os.environ.get("SWEEP_LOG")
            if log:
                time.sleep(0.05)                      # a run takes time: rows come back
                with open(log, "a") as out:
                    out.write(f"{f!r},{c!r}\\n")
                kill_at = int(os.environ.get("SWEEP_KILL_AT", "0"))
                if kill_at:
                    with open(log) as seen:
                        if sum(1 for _ in seen) >= kill_at:
                            os.kill(os.getpid(), signal.SIGKILL)
            amp = 1e-3 * math.exp(-f * c) / 3.0 + math.sqrt(c) / 7.0     # every digit used
            steady = f < 10.5
            return Result(amp, amp / 3e-3, 1.0 / 3.0 + c, 0.1 * f / 3.0, steady,
                          int(f) if steady else None, 1.0 / 3.0)

    FREQS = [9.0, 9.5, 10.0, 10.5, 11.0, 11.5]
    CLEARANCES = [1e-4, 3e-4, 1e-3, 3e-3, 1e-2]

    def run(store, chunksize=1):
        from impactpred.damper.sweep import sweep
        with ThreadPoolExecutor(2) as pool:
            return sweep(Damper(), freq_hz=FREQS, clearance=CLEARANCES, n_cycles=20,
                         executor=pool, progress=False, chunksize=chunksize, store=store)

    if __name__ == "__main__":
        table = run(sys.argv[1])
        with open(sys.argv[2], "wb") as out:
            pickle.dump(table, out)
''')


def _script(tmp_path):
    path = tmp_path / "killable_sweep.py"
    path.write_text(SCRIPT)
    spec = importlib.util.spec_from_file_location("killable_sweep", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return path, module


def _log(path):
    return [tuple(float(v) for v in line.split(",")) for line in path.read_text().split()]


def _stored(store):
    table = pd.read_csv(store, comment="#")
    return list(zip(table["freq_hz"], table["clearance"]))


@pytest.mark.slow                   # two Python processes importing impactpred
def test_a_sweep_killed_halfway_resumes_with_none_lost_and_none_run_twice(tmp_path):
    path, module = _script(tmp_path)
    grid = [(f, c) for f in module.FREQS for c in module.CLEARANCES]
    reference = module.run(None)                      # uninterrupted, no store
    store = tmp_path / "study.csv"
    env = dict(os.environ, SWEEP_LOG=str(tmp_path / "first.log"), SWEEP_KILL_AT="14")
    killed = subprocess.run([sys.executable, str(path), str(store), str(tmp_path / "x.pkl")],
                            env=env, capture_output=True, timeout=300)
    assert killed.returncode == -signal.SIGKILL, killed.stderr.decode()[-2000:]
    done_before = _stored(store)
    assert 8 <= len(done_before) < 14 and len(set(done_before)) == len(done_before)
    env = dict(os.environ, SWEEP_LOG=str(tmp_path / "second.log"))
    resumed = subprocess.run([sys.executable, str(path), str(store), str(tmp_path / "t.pkl")],
                             env=env, capture_output=True, timeout=300)
    assert resumed.returncode == 0, resumed.stderr.decode()[-2000:]
    table = pd.read_pickle(tmp_path / "t.pkl")
    pd.testing.assert_frame_equal(table, reference, check_exact=True)
    run_again = _log(tmp_path / "second.log")
    assert not set(run_again) & set(done_before)               # 0 run twice
    assert sorted(set(run_again) | set(done_before)) == sorted(grid)    # 0 lost
    assert len(run_again) == len(set(run_again))
    final = _stored(store)
    assert sorted(final) == sorted(grid)                      # each stored exactly once
    # a third call runs nothing and returns the same table, read back from the store
    (tmp_path / "second.log").unlink()
    again = module.run(store)
    pd.testing.assert_frame_equal(again, reference, check_exact=True)


@dataclasses.dataclass(frozen=True)
class _Force:
    amplitude: float
    freq_hz: float
    phase: float = 0.0


@dataclasses.dataclass(frozen=True)
class _Result:
    primary_amplitude: float
    reduction: float
    impacts_per_cycle: float
    power_dissipated: float
    is_steady: bool
    steady_state_cycle: int | None
    amplitude_without_damper: float


BROKEN = set()        # clearances that fail while listed: the same damper, fixed later
RUNS = []


@dataclasses.dataclass(frozen=True)
class _Damper:
    damper_mass: float = 0.05
    clearance: float = 1e-3
    contact: object = None
    excitation: _Force = _Force(1.0, 10.0)
    primary_mass: float = 1.0

    def replace(self, **changes):
        return dataclasses.replace(self, **changes)

    def engine(self):
        """No phases to build (a sweep builds each design's engine before any run)."""
        return None

    def simulate(self, n_cycles, **kwargs):
        RUNS.append((self.excitation.freq_hz, self.clearance))
        if self.clearance in BROKEN:
            raise FloatingPointError(f"engine blew up at clearance {self.clearance}")
        value = self.excitation.freq_hz * self.clearance / 3.0
        return _Result(value, 0.1 / 3.0, 2.0, value / 7.0, True, 3, 1e-3 / 3.0)


def _sweep(store, **kwargs):
    with ThreadPoolExecutor(1) as pool:
        return sweep(_Damper(), freq_hz=[9.0, 10.0], clearance=[1e-3, 2e-3, 4e-3],
                     n_cycles=10, executor=pool, progress=False, chunksize=1, store=store,
                     **kwargs)


def test_a_failed_sweep_keeps_its_finished_rows_and_resumes(tmp_path):
    store = tmp_path / "deep" / "study.csv"                    # folders are created
    reference = _sweep(None)
    BROKEN.add(4e-3)
    RUNS.clear()
    try:
        with pytest.raises(SweepError, match=r"clearance=0\.004 failed"):
            _sweep(store)
    finally:
        BROKEN.clear()
    first = set(_stored(store))
    assert first and (9.0, 4e-3) not in first
    RUNS.clear()
    table = _sweep(store)
    pd.testing.assert_frame_equal(table, reference, check_exact=True)
    assert not set(RUNS) & first and len(RUNS) == 6 - len(first)


def test_the_store_format_is_a_header_line_then_csv(tmp_path):
    store = tmp_path / "study.csv"
    table = _sweep(store)
    lines = store.read_text().splitlines()
    assert lines[0].startswith("# impactpred sweep store v1 {")
    assert '"axes": ["freq_hz", "clearance"]' in lines[0] and '"n_cycles": 10' in lines[0]
    assert lines[1] == ",".join(["freq_hz", "clearance", *RESULT_COLUMNS])
    assert len(lines) == 2 + 6
    stored = pd.read_csv(store, comment="#")
    merged = table.merge(stored, on=["freq_hz", "clearance"], suffixes=("", "_s"))
    for column in ("primary_amplitude", "power_dissipated"):     # every digit kept
        assert (merged[column] == merged[column + "_s"]).all()


def test_a_line_cut_short_by_a_kill_is_dropped_and_run_again(tmp_path):
    store = tmp_path / "study.csv"
    reference = _sweep(store)
    text = store.read_text()
    store.write_text(text[:-15])                            # the last row half-written
    RUNS.clear()
    table = _sweep(store)
    pd.testing.assert_frame_equal(table, reference, check_exact=True)
    assert len(RUNS) == 1
    assert store.read_text() == text                        # rewritten whole, once


@pytest.mark.parametrize("damper, axes, n_cycles, match", [
    (_Damper(), {"freq_hz": [9.0, 10.0], "clearance": [1e-3]}, 11,
     "n_cycles=10, not this one"),
    (_Damper(damper_mass=0.06), {"freq_hz": [9.0], "clearance": [1e-3]}, 10,
     "another base damper"),
    (_Damper(), {"freq_hz": [9.0]}, 10, r"axes=\['freq_hz', 'clearance'\]"),
])
def test_a_store_of_another_study_is_refused(tmp_path, damper, axes, n_cycles, match):
    store = tmp_path / "study.csv"
    _sweep(store)
    with pytest.raises(ValueError, match=match):
        sweep(damper, **axes, n_cycles=n_cycles, executor=1, progress=False, store=store)


def test_a_file_that_is_not_a_store_is_refused(tmp_path):
    other = tmp_path / "notes.csv"
    other.write_text("a,b\n1,2\n")
    with pytest.raises(ValueError, match="is not a sweep store"):
        _sweep(other)
    with pytest.raises(ValueError, match="is a directory"):
        _sweep(tmp_path)
    with pytest.raises(TypeError, match="store must be a file path.*got 3"):
        _sweep(3)
