"""impactpred.parallel: executor resolution, ordered and as-completed mapping, progress; and
the parallel entry points (sweep, uncertainty band, benchmark) on a Dask LocalCluster the
test starts itself, against their serial runs (bit-identical)."""

from __future__ import annotations

import functools
import io
import os
from concurrent.futures import Executor, Future, ProcessPoolExecutor, ThreadPoolExecutor

import numpy as np
import pandas as pd
import pytest
from threadpoolctl import threadpool_limits

from impactpred.parallel import (
    InlineExecutor,
    _one_blas_thread,
    check_executor,
    progress_bar,
    resolve_executor,
)


def _square(x):
    return x * x


def _fail_on(x, bad):
    if x == bad:
        raise ZeroDivisionError(f"task {x}")
    return x


# ---------------------------------------------------------------------------- resolution
def test_none_is_a_process_pool_of_every_core_shut_down_on_leaving():
    with resolve_executor(None) as pool:
        assert pool.kind == "processes" and pool.owned
        assert isinstance(pool.executor, ProcessPoolExecutor)
        assert pool.workers == (os.cpu_count() or 1)
        executor = pool.executor
        assert pool.map(_square, [(i,) for i in range(5)]) == [0, 1, 4, 9, 16]
    with pytest.raises(RuntimeError, match="shutdown"):
        executor.submit(_square, 2)


def test_counts_one_is_this_process_and_n_a_pool_of_n():
    pool = resolve_executor(1)
    assert pool.kind == "inline" and pool.workers == 1 and not pool.owned
    assert pool.map(_square, [(3,), (4,)]) == [9, 16]
    with resolve_executor(np.int64(2)) as pool:
        assert pool.kind == "processes" and pool.workers == 2
    assert resolve_executor(None, default=1).kind == "inline"


def test_a_callers_executor_is_used_and_left_running():
    with ThreadPoolExecutor(3) as threads:
        with resolve_executor(threads) as pool:
            assert pool.kind == "executor" and pool.workers == 3 and not pool.owned
            assert pool.map(_square, [(i,) for i in range(10)]) == [i * i for i in range(10)]
        assert threads.submit(_square, 5).result() == 25          # still running


def test_a_client_is_duck_typed_by_get_executor_without_importing_dask():
    calls = []

    class Client:                           # what resolve_executor needs of a Dask client
        def get_executor(self, **kwargs):
            calls.append(kwargs)
            return ThreadPoolExecutor(2)

    pool = resolve_executor(Client())
    assert pool.kind == "dask" and not pool.owned and calls == [{"pure": False}]
    assert pool.map(_square, [(2,), (3,)]) == [4, 9]
    pool.executor.shutdown()
    check_executor(Client())


def test_local_cluster_refuses_bad_counts_before_starting_anything():
    from impactpred.parallel import local_cluster

    with pytest.raises(ValueError, match="n_workers must be an integer >= 1, got 0"):
        local_cluster(n_workers=0)
    with pytest.raises(TypeError, match="threads_per_worker must be an integer >= 1, got 1.5"):
        local_cluster(threads_per_worker=1.5)
    with pytest.raises(TypeError, match="got True"):
        local_cluster(n_workers=True)


@pytest.mark.parametrize("given, workers", [("local", os.cpu_count() or 1), ("local:3", 3),
                                            ("tcp://host:8786", None), ("host:8786", None)])
def test_the_cli_scheduler_local_n_starts_a_local_cluster_of_n(given, workers):
    from impactpred.cli import _local_workers

    assert _local_workers(given) == workers


@pytest.mark.parametrize("bad", ["local:0", "local:two", "local:-1"])
def test_the_cli_scheduler_refuses_a_bad_local_count(bad):
    from impactpred.cli import _local_workers

    with pytest.raises(ValueError, match=f"worker count N >= 1, got '{bad}'"):
        _local_workers(bad)


def test_dask_outcomes_become_concurrent_futures():
    from concurrent.futures import CancelledError

    from impactpred.parallel import _resolved

    assert _resolved("finished", 7).result() == 7
    try:
        raise ZeroDivisionError("remote")
    except ZeroDivisionError as exc:
        triple = (type(exc), exc, exc.__traceback__)
    failed = _resolved("error", triple)
    assert isinstance(failed.exception(), ZeroDivisionError)
    assert failed.exception().__traceback__ is not None
    with pytest.raises(CancelledError):
        _resolved("cancelled", CancelledError()).result()
    with pytest.raises(RuntimeError, match="ended as 'lost'"):
        _resolved("lost", None).result()


def test_one_blas_thread_inside_a_task_and_restored_after():
    from threadpoolctl import threadpool_info

    def blas_threads():
        return [i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"]

    with threadpool_limits(limits=2, user_api="blas"):
        before = blas_threads()
        inside = _one_blas_thread(blas_threads)
        inside_again = _one_blas_thread(blas_threads)          # the remembered controller
        assert blas_threads() == before
    assert inside and set(inside) == {1} and inside_again == inside


@pytest.mark.parametrize("bad, error, match", [
    ("processes", TypeError, "executor must be a concurrent.futures.Executor"),
    (True, TypeError, "got True"),
    (2.0, TypeError, "got 2.0"),
    (0, ValueError, "worker count must be >= 1, got 0"),
])
def test_bad_executors_are_refused_naming_the_value(bad, error, match):
    with pytest.raises(error, match=match):
        resolve_executor(bad)
    with pytest.raises(error, match=match):
        check_executor(bad)


def test_counts_refused_where_an_entry_point_takes_none():
    with pytest.raises(TypeError, match="band_executor.*or None, got 2"):
        check_executor(2, name="band_executor", counts=False)


# ------------------------------------------------------------------------------ mapping
def test_as_completed_yields_every_index_once_and_map_keeps_order():
    with ThreadPoolExecutor(4) as threads:
        pool = resolve_executor(threads)
        seen = sorted(i for i, f in pool.as_completed(_square, [(i,) for i in range(20)]))
        assert seen == list(range(20))
        assert pool.map(_square, [(i,) for i in range(20)]) == [i * i for i in range(20)]


def test_inline_runs_each_task_only_when_the_previous_one_is_taken():
    ran = []

    def task(i):
        ran.append(i)
        return i

    pool = resolve_executor(1)
    for index, future in pool.as_completed(task, [(0,), (1,), (2,)]):
        assert ran == list(range(index + 1))
        assert future.result() == index


def test_a_task_exception_reaches_the_caller_and_stops_the_rest():
    with ThreadPoolExecutor(1) as threads:
        pool = resolve_executor(threads)
        with pytest.raises(ZeroDivisionError, match="task 3"):
            pool.map(_fail_on, [(i, 3) for i in range(50)])
    with pytest.raises(ZeroDivisionError, match="task 1"):
        resolve_executor(1).map(_fail_on, [(i, 1) for i in range(3)])
    future = InlineExecutor().submit(_fail_on, 1, 1)
    assert isinstance(future.exception(), ZeroDivisionError)


def test_map_advances_a_progress_bar_per_task():
    stream = io.StringIO()
    bar = progress_bar(4, desc="work", file=stream, mininterval=0.0, miniters=1)
    resolve_executor(1).map(_square, [(i,) for i in range(4)], progress=bar)
    bar.close()
    assert bar.n == 4 and "work" in stream.getvalue() and "4/4" in stream.getvalue()
    quiet = io.StringIO()
    bar = progress_bar(4, enabled=False, file=quiet)
    resolve_executor(1).map(_square, [(i,) for i in range(4)], progress=bar)
    bar.close()
    assert quiet.getvalue() == ""


class _CountingExecutor(Executor):
    """Runs tasks inline and counts them: the band's tasks go through the executor."""

    def __init__(self):
        self.submitted = []

    def submit(self, fn, /, *args, **kwargs):
        if fn is _one_blas_thread:                 # every task runs with one BLAS thread
            fn, args = args[0], args[1:]
            with threadpool_limits(limits=1, user_api="blas"):
                return self.submit(fn, *args, **kwargs)
        self.submitted.append(getattr(fn, "__name__", None) or fn.func.__name__)
        future = Future()
        future.set_result(fn(*args, **kwargs))
        return future


# ----------------------------------------------------------------- the entry points' data
def _real_damper():
    from data_synth import SpringMass
    from impactpred.damper import HarmonicForce, ImpactDamper, InstantaneousImpact

    primary = SpringMass(1.0, 4 * np.pi**2 * 100.0, damping_ratio=0.02)       # 10 Hz
    return ImpactDamper(primary, damper_mass=0.05, clearance=5e-3,
                        contact=InstantaneousImpact(0.6),
                        excitation=HarmonicForce(1.0, 10.0))


@functools.cache
def _band_inputs():
    from data_synth import LumpedMass, Rod, lightly_damped
    from impactpred import Rigid
    from impactpred.predict import _solve_pair
    from impactpred.truncation import identified_model
    from modalid import FRFData, ModalFit

    truth = lightly_damped(Rod(1.0, 1.0, support="fixed"), 20, 1e-3)
    freq = np.linspace(0.01, 5.25, 2100)                     # 10 modes in the band
    rng = np.random.default_rng(0)
    h = truth.frf(2 * np.pi * freq)
    h = h * (1 + 0.01 * (rng.standard_normal(h.size) + 1j * rng.standard_normal(h.size)))
    fit = ModalFit().fit(FRFData(freq, h))
    # a partial of a module-level function: it pickles (process pools need that)
    solve = functools.partial(_solve_pair, velocity1=1.0, velocity2=0.0, check_passive=True,
                              gap=0.0, contact=Rigid(), t_end=8.0, dt=None, method="laplace")
    return [LumpedMass(1.0), identified_model(fit)], [None, fit], solve


def _same_band(a, b):
    assert a.variants == b.variants                      # every variant's figures, exactly
    assert (a.nominal, a.low, a.high) == (b.nominal, b.low, b.high)
    assert (a.truncation, a.tail, a.spread, a.pole_spread, a.level) == (
        b.truncation, b.tail, b.spread, b.pole_spread, b.level)


def test_band_tasks_go_through_the_executor_and_the_band_is_unchanged():
    from impactpred.uncertainty import uncertainty_band

    models, fits, solve = _band_inputs()
    serial = uncertainty_band(models, fits, solve, n_draws=2, fractions=(0.6, 0.8))
    counting = _CountingExecutor()
    pooled = uncertainty_band(models, fits, solve, n_draws=2, fractions=(0.6, 0.8),
                              executor=counting)
    _same_band(serial, pooled)
    # 2 refits, the tail's solve, 2 cut-band solves, 2 residue draws and 2 pole draws
    assert sorted(counting.submitted) == sorted(["refit_on_cut_band"] * 2
                                                + ["_solve_pair"] * 7)
    with pytest.raises(TypeError, match="executor"):
        uncertainty_band(models, fits, solve, executor=2)


def test_band_on_a_thread_pool_leaves_the_warning_filters_as_they_were():
    """The variants' warnings are dropped by one filter in the calling thread: a filter
    per task (catch_warnings on a thread pool) could leave "ignore" behind for good, and
    every later warning of the session lost."""
    import warnings

    from impactpred.uncertainty import uncertainty_band

    models, fits, solve = _band_inputs()
    before = list(warnings.filters)
    with ThreadPoolExecutor(2) as pool:
        for _ in range(4):
            uncertainty_band(models, fits, solve, n_draws=4, executor=pool)
    assert warnings.filters == before
    with pytest.warns(UserWarning, match="still heard"):
        warnings.warn("still heard", UserWarning, stacklevel=1)


def test_band_in_a_process_pool_is_bit_identical_to_serial():
    from impactpred.uncertainty import uncertainty_band

    models, fits, solve = _band_inputs()
    serial = uncertainty_band(models, fits, solve, n_draws=2)
    with ProcessPoolExecutor(2) as pool:
        pooled = uncertainty_band(models, fits, solve, n_draws=2, executor=pool)
    _same_band(serial, pooled)


# --------------------------------------------------------------------- a Dask LocalCluster
@pytest.fixture(scope="module")
def client():
    distributed = pytest.importorskip("dask.distributed")
    from impactpred.parallel import local_cluster

    # the library's cluster: two worker processes of one thread each, no dashboard (no
    # port, no bokeh), no profiler, no MALLOC_TRIM_THRESHOLD_
    with local_cluster(n_workers=2) as cluster, distributed.Client(cluster) as client:
        yield client


def _worker_setup():
    import dask

    return (os.environ.get("MALLOC_TRIM_THRESHOLD_"), os.environ.get("OMP_NUM_THREADS"),
            dask.config.get("distributed.worker.profile.enabled"))


@pytest.mark.slow
def test_local_cluster_starts_tuned_workers_and_leaves_the_config_alone(client):
    import dask

    setups = list(client.run(_worker_setup).values())
    assert len(setups) == 2 and all(c == 1 for c in client.nthreads().values())
    # the trim threshold is glibc's own unless this process already carried one
    inherited = os.environ.get("MALLOC_TRIM_THRESHOLD_")
    assert setups == [(inherited, "1", False)] * 2
    assert dask.config.get("distributed.worker.profile.enabled") is True      # not left set
    assert "MALLOC_TRIM_THRESHOLD_" in dask.config.get("distributed.nanny.pre-spawn-environ")


@pytest.mark.slow
def test_a_client_maps_a_batch_at_once_in_order_with_exceptions(client, monkeypatch):
    pool = resolve_executor(client)
    assert pool.kind == "dask" and pool.client is client and pool.workers == 2
    calls = []
    real_map = client.map

    def counting_map(*args, **kwargs):
        calls.append(len(args[1]))
        return real_map(*args, **kwargs)

    monkeypatch.setattr(client, "map", counting_map)
    assert pool.map(_square, [(i,) for i in range(30)]) == [i * i for i in range(30)]
    assert calls == [30]                                # one call for the 30 tasks
    assert sorted(i for i, _ in pool.as_completed(_square, [(i,) for i in range(7)])) == \
        list(range(7))
    with pytest.raises(ZeroDivisionError, match="task 3"):
        pool.map(_fail_on, [(i, 3) for i in range(6)])
    # a ClientExecutor given directly submits task by task, with the same results
    assert resolve_executor(client.get_executor()).map(_square, [(2,), (5,)]) == [4, 25]


@pytest.mark.slow
def test_sweep_on_a_local_cluster_equals_the_serial_sweep(client):
    from impactpred.damper.sweep import sweep

    damper = _real_damper()
    grid = {"freq_hz": [9.0, 10.5, 11.0], "clearance": [3e-3, 6e-3]}
    serial = sweep(damper, **grid, n_cycles=20, executor=1, progress=False)
    on_client = sweep(damper, **grid, n_cycles=20, executor=client, progress=False,
                      chunksize=1)
    pd.testing.assert_frame_equal(on_client, serial, check_exact=True)
    on_executor = sweep(damper, **grid, n_cycles=20, executor=client.get_executor(),
                        progress=False)
    pd.testing.assert_frame_equal(on_executor, serial, check_exact=True)


@pytest.mark.slow
def test_band_on_a_local_cluster_equals_the_serial_band(client):
    from impactpred.uncertainty import uncertainty_band

    models, fits, solve = _band_inputs()
    serial = uncertainty_band(models, fits, solve, n_draws=2)
    _same_band(serial, uncertainty_band(models, fits, solve, n_draws=2, executor=client))


@pytest.mark.slow
def test_benchmark_on_a_local_cluster_equals_the_serial_benchmark(client):
    from impactpred.benchmark import run_benchmark

    options = {"cases": ("mass-rod M/m=1",), "bands": (8, 10), "noises": (0.01,),
               "band_modes": (), "progress": False}
    serial = run_benchmark(workers=1, **options)
    distributed = run_benchmark(executor=client, **options)
    timing = [c for c in serial.columns if c.startswith("t_")]
    pd.testing.assert_frame_equal(distributed.drop(columns=timing),
                                  serial.drop(columns=timing), check_exact=True)
    assert len(serial) == 2

