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
  Dask is never imported here), whose executor submits with ``pure=False``.

Tasks are shipped as ``fn(*args)``: under processes or Dask, ``fn`` must be importable (a
module-level function) and the arguments picklable. The results are whatever ``fn``
returns, unchanged: the parallel entry points are bit-identical to their serial runs.
Every task runs with one BLAS thread (:func:`_one_blas_thread`), wherever it runs: Dask
workers and process pools would otherwise run it single-threaded and this process with
all its cores, and a threaded BLAS sums in another order (results differing in the last
bits); the tasks' linear algebra is small, where threads only add overhead.
"""

from __future__ import annotations

import numbers
import os
import sys
from concurrent.futures import FIRST_COMPLETED, Executor, Future, ProcessPoolExecutor, wait

from threadpoolctl import threadpool_limits

__all__ = ["InlineExecutor", "Pool", "check_executor", "progress_bar", "resolve_executor"]


def _one_blas_thread(fn, *args):
    """``fn(*args)`` with BLAS limited to one thread (see the module docstring)."""
    with threadpool_limits(limits=1, user_api="blas"):
        return fn(*args)


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
    """

    def __init__(self, executor, *, workers, kind, owned):
        self.executor, self.workers, self.kind, self.owned = executor, workers, kind, owned

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
        return Pool(inner, workers=_count(inner), kind="dask", owned=False)
    raise TypeError(f"{name} must be a concurrent.futures.Executor, a dask.distributed.Client"
                    f" (anything with get_executor()), a worker count or None, got "
                    f"{executor!r}")


def progress_bar(total, *, enabled=True, desc=None, unit="it", bar_format=None, file=None,
                 mininterval=0.1, **options):
    """A ``tqdm`` bar on stderr (``file``), or a disabled one that prints nothing.

    Parameters
    ----------
    total : int
        Units of work.
    enabled : bool
        False: nothing is printed (the bar still counts).
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

    return tqdm(total=total, disable=not enabled, desc=desc, unit=unit,
                bar_format=bar_format, file=sys.stderr if file is None else file,
                mininterval=mininterval, dynamic_ncols=False, **options)
