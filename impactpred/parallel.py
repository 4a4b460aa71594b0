"""Where parallel work runs: the one resolution of ``executor=`` for every parallel entry point.

:func:`resolve_executor` turns what a user passes as ``executor=`` into a :class:`Pool`,
something to submit tasks to and to collect them from, in order or as they finish, with an
optional progress bar (:func:`progress_bar`, from tqdm). Accepted:

* ``None``: the entry point's default (a process pool of every core for a sweep, this
  process for the uncertainty band);
* an ``int`` (where the entry point takes a worker count): ``1`` runs in this process,
  ``n > 1`` in a ``ProcessPoolExecutor(n)`` created and shut down by the pool;
* any ``concurrent.futures.Executor`` (a process or thread pool of the caller's, a Dask
  ``client.get_executor()``), left running;
* a ``dask.distributed.Client``, recognised by its ``get_executor`` method (duck-typed:
  Dask is imported only once a client is given), whose executor submits with
  ``pure=False``; a batch of tasks (:meth:`Pool.as_completed`, :meth:`Pool.map`) goes to
  the scheduler in one ``client.map`` call instead of one message per task.

:func:`local_cluster` starts a Dask ``LocalCluster`` set up for these tasks (one thread
per worker process, no sampling profiler, no ``MALLOC_TRIM_THRESHOLD_``): the cluster to
use on one machine, or to copy the settings of for workers started by other means.

Tasks are shipped as ``fn(*args)``: under processes or Dask, ``fn`` must be importable (a
module-level function) and the arguments picklable. The results are whatever ``fn``
returns, unchanged: the parallel entry points are bit-identical to their serial runs.
Every task runs with one BLAS thread (:func:`_one_blas_thread`), wherever it runs: Dask
workers and process pools would otherwise run it single-threaded and this process with
all its cores, and a threaded BLAS sums in another order (results differing in the last
bits); the tasks' linear algebra is small, where threads only add overhead. The limit is set
through a ``threadpoolctl.ThreadpoolController`` remembered per process (rebuilt when new
modules have been imported): finding the loaded libraries costs ~4 ms, every task.
"""

from __future__ import annotations

import functools
import numbers
import os
import sys
from concurrent.futures import (
    FIRST_COMPLETED,
    CancelledError,
    Executor,
    Future,
    ProcessPoolExecutor,
    wait,
)

import numpy as np
from threadpoolctl import ThreadpoolController

__all__ = ["InlineExecutor", "Pool", "check_executor", "local_cluster", "progress_bar",
           "resolve_executor"]


@functools.lru_cache(maxsize=2)
def _controller(n_modules):
    """This process's thread-pool libraries, found again when ``len(sys.modules)`` changes."""
    return ThreadpoolController()


def one_blas_thread():
    """A context in which BLAS runs on one thread (see the module docstring).

    ``solve_impact`` solves in it: its dense algebra is small (phase matrices of tens to
    hundreds of states), and on a machine whose other cores are busy BLAS threads made a
    69-state exact solve 5-15 times slower (0.2-0.56 s against 0.03-0.07 s).
    """
    return _controller(len(sys.modules)).limit(limits=1, user_api="blas")


def _one_blas_thread(fn, *args):
    """``fn(*args)`` with BLAS limited to one thread (see the module docstring)."""
    with one_blas_thread():
        return fn(*args)


def _resolved(status, result):
    """A finished ``concurrent.futures.Future`` holding a Dask task's outcome.

    ``status``: the Dask future's; ``result``: the value, an ``(type, exception,
    traceback)`` triple for a failed task, a ``CancelledError`` for a cancelled one.
    """
    future = Future()
    if status == "finished":
        future.set_result(result)
    elif isinstance(result, tuple) and len(result) == 3 and isinstance(result[1], BaseException):
        future.set_exception(result[1].with_traceback(result[2]))
    elif isinstance(result, BaseException):
        future.set_exception(result)
    else:
        future.set_exception(RuntimeError(f"Dask task ended as {status!r}: {result!r}"))
    return future


class InlineExecutor(Executor):
    """Runs each task when it is submitted, in this process (the serial run)."""

    def submit(self, fn, /, *args, **kwargs):
        """Run ``fn(*args, **kwargs)`` now.

        Parameters
        ----------
        fn : callable
        *args, **kwargs
            Its arguments.

        Returns
        -------
        concurrent.futures.Future
            Done: its result, or the exception ``fn`` raised.
        """
        future = Future()
        try:
            future.set_result(fn(*args, **kwargs))
        except Exception as exc:  # noqa: BLE001 -- handed over to the caller, as a pool does
            future.set_exception(exc)
        return future


def _count(executor) -> int:
    """Workers behind ``executor`` (threads of a Dask cluster; ``os.cpu_count()`` if unknown)."""
    client = getattr(executor, "_client", None)          # a Dask ClientExecutor
    if client is not None and hasattr(client, "nthreads"):
        try:
            return max(1, int(sum(client.nthreads().values())))
        except Exception:  # noqa: BLE001 -- a scheduler that cannot answer: guess
            return os.cpu_count() or 1
    return int(getattr(executor, "_max_workers", None) or os.cpu_count() or 1)


class Pool:
    """An executor resolved by :func:`resolve_executor`, with its worker count.

    Attributes
    ----------
    executor : concurrent.futures.Executor
        Where the tasks go.
    workers : int
        Workers behind it (1 in this process; a Dask cluster's threads).
    kind : str
        ``"inline"``, ``"processes"`` (a pool created here), ``"dask"`` or ``"executor"``
        (the caller's).
    owned : bool
        Whether :meth:`close` shuts the executor down (created here).
    client : dask.distributed.Client or None
        The Dask client a batch of tasks is mapped on at once (given as ``executor=``).
    """

    def __init__(self, executor, *, workers, kind, owned, client=None):
        self.executor, self.workers, self.kind, self.owned = executor, workers, kind, owned
        self.client = client

    def _on_client(self, fn, tasks):
        """:meth:`as_completed` on a Dask client: every task in one ``client.map`` call
        (one graph update for the scheduler, not one per task), the results of each batch
        of finished tasks fetched in one ``client.gather``."""
        from dask.distributed import as_completed   # a Client was given: Dask is installed

        columns = [list(column) for column in zip(*tasks)]
        remote = self.client.map(_one_blas_thread, [fn] * len(tasks), *columns, pure=False)
        index = {future.key: i for i, future in enumerate(remote)}
        try:
            for batch in as_completed(remote).batches():
                batch = sorted(batch, key=lambda future: index[future.key])
                finished = [future for future in batch if future.status == "finished"]
                values = dict(zip([future.key for future in finished],
                                  self.client.gather(finished))) if finished else {}
                for future in batch:
                    if future.key in values:
                        outcome = values[future.key]
                    elif future.status == "error":
                        exc = future.exception()
                        outcome = (type(exc), exc, future.traceback())
                    else:
                        outcome = CancelledError(f"Dask task {future.key!r} was cancelled")
                    yield index[future.key], _resolved(future.status, outcome)
        finally:
            unfinished = [future for future in remote if not future.done()]
            if unfinished:
                self.client.cancel(unfinished)

    def submit(self, fn, /, *args) -> Future:
        """``executor.submit(fn, *args)``.

        Parameters
        ----------
        fn : callable
            Picklable for a process pool or a Dask cluster (a module-level function).
        *args
            Its arguments.

        Returns
        -------
        concurrent.futures.Future
        """
        return self.executor.submit(_one_blas_thread, fn, *args)

    def as_completed(self, fn, tasks):
        """Run ``fn(*args)`` for every ``args`` of ``tasks``; yield ``(index, future)`` as
        each finishes (in order when inline: each runs only when the previous one is done).

        A task's exception is left in its future. Leaving the generator early (an
        exception in the caller's loop, ``close()``) cancels the tasks not yet started.

        Parameters
        ----------
        fn : callable
        tasks : iterable of tuple
            The arguments of each call.

        Returns
        -------
        generator of (int, concurrent.futures.Future)
            The task's index in ``tasks`` and its finished future.
        """
        tasks = list(tasks)
        if self.kind == "inline":
            for index, args in enumerate(tasks):
                yield index, self.executor.submit(_one_blas_thread, fn, *args)
            return
        if self.client is not None and tasks and len({len(args) for args in tasks}) == 1:
            yield from self._on_client(fn, tasks)
            return
        futures = {}
        try:
            for index, args in enumerate(tasks):
                futures[self.executor.submit(_one_blas_thread, fn, *args)] = index
            pending = set(futures)
            while pending:
                done, pending = wait(pending, return_when=FIRST_COMPLETED)
                for future in sorted(done, key=futures.__getitem__):
                    yield futures[future], future
        finally:
            for future in futures:
                future.cancel()

    def map(self, fn, tasks, *, progress=None):
        """``[fn(*args) for args in tasks]``, run on the pool; the first exception raised.

        Parameters
        ----------
        fn : callable
        tasks : iterable of tuple
            The arguments of each call.
        progress : tqdm bar, optional, keyword-only
            A :func:`progress_bar` advanced by one per finished task.

        Returns
        -------
        list
            The results, in the order of ``tasks``.
        """
        tasks = list(tasks)
        results = [None] * len(tasks)
        for index, future in self.as_completed(fn, tasks):
            results[index] = future.result()
            if progress is not None:
                progress.update(1)
        return results

    def close(self, *, cancel=False):
        """Shut the executor down if it was created here; a caller's is left running.

        Parameters
        ----------
        cancel : bool, keyword-only
            Drop the tasks not yet started instead of waiting for them.

        Returns
        -------
        None
        """
        if self.owned:
            self.owned = False
            self.executor.shutdown(wait=not cancel, cancel_futures=cancel)

    def __enter__(self):
        return self

    def __exit__(self, kind, exc, tb):
        self.close(cancel=exc is not None)
        return False


def check_executor(executor, *, name="executor", counts=True) -> None:
    """Raise ``TypeError`` (``ValueError`` for a count < 1) unless :func:`resolve_executor`
    takes ``executor``; nothing is created.

    Parameters
    ----------
    executor : None, int, concurrent.futures.Executor or dask.distributed.Client
    name : str, keyword-only
        The argument's name in the message.
    counts : bool, keyword-only
        Whether a worker count is allowed.

    Returns
    -------
    None
    """
    if executor is None or isinstance(executor, Executor) or (
            not isinstance(executor, numbers.Integral)
            and callable(getattr(executor, "get_executor", None))):
        return
    if counts and isinstance(executor, numbers.Integral) and not isinstance(executor, bool):
        if executor < 1:
            raise ValueError(f"{name} as a worker count must be >= 1, got {executor}")
        return
    raise TypeError(f"{name} must be a concurrent.futures.Executor, a dask.distributed.Client"
                    f" (anything with get_executor()){', a worker count' if counts else ''}"
                    f" or None, got {executor!r}")


def resolve_executor(executor=None, *, default=None, name="executor") -> Pool:
    """A :class:`Pool` for ``executor`` (see the module's docstring).

    Parameters
    ----------
    executor : None, int, concurrent.futures.Executor or dask.distributed.Client
        What the caller gave.
    default : None or int
        What ``None`` means: ``None`` a process pool of ``os.cpu_count()`` workers, an
        integer as if it were given (1: this process).
    name : str
        The argument's name in error messages.

    Returns
    -------
    Pool
        Use it as a context manager: a pool created here is shut down on leaving.

    Raises
    ------
    TypeError
        Anything else (a string, a bool, a float).
    ValueError
        A worker count below 1.
    """
    if executor is None:
        executor = default
        if executor is None:
            workers = os.cpu_count() or 1
            return Pool(ProcessPoolExecutor(max_workers=workers), workers=workers,
                        kind="processes", owned=True)
    if isinstance(executor, bool) or isinstance(executor, (str, bytes)):
        raise TypeError(f"{name} must be a concurrent.futures.Executor, a dask.distributed."
                        f"Client, a worker count or None, got {executor!r}")
    if isinstance(executor, numbers.Integral):
        workers = int(executor)
        if workers < 1:
            raise ValueError(f"{name} as a worker count must be >= 1, got {workers}")
        if workers == 1:
            return Pool(InlineExecutor(), workers=1, kind="inline", owned=False)
        return Pool(ProcessPoolExecutor(max_workers=workers), workers=workers,
                    kind="processes", owned=True)
    if isinstance(executor, InlineExecutor):
        return Pool(executor, workers=1, kind="inline", owned=False)
    if isinstance(executor, Executor):
        kind = "dask" if getattr(executor, "_client", None) is not None else "executor"
        return Pool(executor, workers=_count(executor), kind=kind, owned=False)
    get_executor = getattr(executor, "get_executor", None)
    if callable(get_executor):                            # a dask.distributed.Client
        inner = get_executor(pure=False)
        client = executor if callable(getattr(executor, "map", None)) else None
        return Pool(inner, workers=_count(inner), kind="dask", owned=False, client=client)
    raise TypeError(f"{name} must be a concurrent.futures.Executor, a dask.distributed.Client"
                    f" (anything with get_executor()), a worker count or None, got "
                    f"{executor!r}")


#: The Dask configuration :func:`local_cluster` starts its workers with.
_TUNED = {
    # each worker's sampling profiler (a stack sample every 10 ms) runs in every task
    "distributed.worker.profile.enabled": False,
    # Dask's nannies also set MALLOC_TRIM_THRESHOLD_=65536, and glibc then returns freed
    # memory at once: the engine's many small arrays turn into mmap/munmap system calls
    # (~1.5x the CPU time of a damper run). Left out: glibc's adaptive default.
    "distributed.nanny.pre-spawn-environ": {"OMP_NUM_THREADS": 1, "MKL_NUM_THREADS": 1,
                                            "OPENBLAS_NUM_THREADS": 1},
}


def local_cluster(*, n_workers=None, threads_per_worker=1, processes=True,
                  dashboard_address=None, **options):
    """A Dask ``LocalCluster`` set up for sweeps, uncertainty bands and the benchmark.

    Dask's defaults cost these tasks about 1.6x the CPU time of a process pool (see
    ``benchmarks/bench_scaling.py``); the workers started here run them at the pool's
    speed: one thread per worker process (the tasks hold the GIL), the workers' sampling
    profiler off, and glibc's own memory-trimming threshold instead of Dask's
    ``MALLOC_TRIM_THRESHOLD_=65536``; BLAS and OpenMP on one thread, as Dask sets them.
    The settings apply while the cluster starts (``dask.config.set`` around it, nothing
    left set): workers added later (``cluster.scale``) get the configuration current then.

    Parameters
    ----------
    n_workers : int or None, keyword-only
        Worker processes; ``None``: ``os.cpu_count()``.
    threads_per_worker : int, keyword-only
        Threads per worker (1: the tasks are CPU-bound Python and compiled loops).
    processes : bool, keyword-only
        Worker processes (True) or threads of this process.
    dashboard_address : str or None, keyword-only
        Where to serve Dask's dashboard (needs bokeh), e.g. ``":8787"``; ``None``: none.
    **options
        Any other ``dask.distributed.LocalCluster`` option.

    Returns
    -------
    dask.distributed.LocalCluster
        Running; close it (or use it as a context manager). Pass
        ``dask.distributed.Client(cluster)`` as ``executor=`` of ``sweep``,
        ``uncertainty_band`` or ``run_benchmark``.

    Raises
    ------
    ImportError
        Dask is not installed (``pip install 'impactpred[distributed]'``).
    TypeError, ValueError
        ``n_workers`` or ``threads_per_worker`` not an integer >= 1.

    Notes
    -----
    A process that already holds ``MALLOC_TRIM_THRESHOLD_`` in its environment (set by
    hand, or by an earlier cluster started with Dask's defaults, whose nannies write it
    into this process's ``os.environ``) passes it on to the workers.

    Examples
    --------
    >>> from dask.distributed import Client
    >>> from impactpred.parallel import local_cluster
    >>> with local_cluster(n_workers=2) as cluster, Client(cluster) as client:  # doctest: +SKIP
    ...     table = sweep(damper, freq_hz=f, clearance=c, executor=client)
    """
    for name, value in (("n_workers", n_workers), ("threads_per_worker", threads_per_worker)):
        if value is None and name == "n_workers":
            continue
        if isinstance(value, bool) or not isinstance(value, numbers.Integral):
            raise TypeError(f"{name} must be an integer >= 1, got {value!r}")
        if value < 1:
            raise ValueError(f"{name} must be an integer >= 1, got {value}")
    try:
        import dask
        from dask.distributed import LocalCluster
    except ImportError as exc:
        raise ImportError("local_cluster needs Dask: pip install 'impactpred[distributed]'"
                          ) from exc
    with dask.config.set(_TUNED):
        return LocalCluster(n_workers=int(n_workers or os.cpu_count() or 1),
                            threads_per_worker=int(threads_per_worker),
                            processes=bool(processes), dashboard_address=dashboard_address,
                            **options)


#: a bar asked for as ``"auto"`` appears once its run has taken this long (s)
AUTO_PROGRESS_DELAY = 10.0


def check_progress(progress):
    """``progress`` as :func:`progress_bar`'s ``enabled`` takes it: ``"auto"``, or a
    ``bool`` (a numpy bool made one); ``TypeError`` for anything else."""
    if isinstance(progress, str) and progress == "auto":
        return progress
    if isinstance(progress, (bool, np.bool_)):
        return bool(progress)
    raise TypeError(f"progress must be True, False or 'auto', got {progress!r}")


def progress_bar(total, *, enabled=True, desc=None, unit="it", bar_format=None, file=None,
                 mininterval=0.1, **options):
    """A ``tqdm`` bar on stderr (``file``), or a disabled one that prints nothing.

    Parameters
    ----------
    total : int or None
        Units of work (None: counted without a total).
    enabled : bool or "auto"
        False: nothing is printed (the bar still counts); ``"auto"``: the bar appears
        only once the work has taken :data:`AUTO_PROGRESS_DELAY` seconds (a long run
        says so, a short one prints nothing).
    desc, unit, bar_format, mininterval, **options
        As ``tqdm.tqdm``'s (``miniters=1`` with ``mininterval=0``: a redraw at every
        update).
    file : file-like or None
        Where to draw; ``None``: ``sys.stderr`` as it is at the call.

    Returns
    -------
    tqdm.tqdm
        Advance with ``update(n)``; ``close()`` (or a ``with`` block) ends the line.
    """
    from tqdm import tqdm

    if isinstance(enabled, str) and enabled == "auto":
        enabled, options = True, {"delay": AUTO_PROGRESS_DELAY, **options}
    return tqdm(total=total, disable=not enabled, desc=desc, unit=unit,
                bar_format=bar_format, file=sys.stderr if file is None else file,
                mininterval=mininterval, dynamic_ncols=False, **options)
