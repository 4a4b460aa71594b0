"""Design sweeps of an impact damper, run in parallel on any executor or Dask cluster, resumable.

:func:`sweep` runs :meth:`ImpactDamper.simulate` over the Cartesian product of up to four
axes (excitation frequency, mass ratio, clearance, contact stiffness) and returns one row
of scalars per combination as a pandas DataFrame; :func:`optimum_clearance` and
:func:`plot_optimum_clearance` read the clearance that minimises the primary amplitude out
of such a table.

Only the public API of the damper is used (``replace``, ``simulate``, ``primary_mass``,
``excitation``, ``contact`` and the result's summary attributes), so any object with that
interface can be swept.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import os
import pickle
import traceback
import warnings
from contextlib import closing

import numpy as np
import pandas as pd

from modalid.validation import as_count

from ..parallel import check_executor, progress_bar, resolve_executor
from ._sweep_store import SweepStore

__all__ = ["SweepError", "optimum_clearance", "plot_optimum_clearance", "sweep"]

#: Swept axes, in the order of the grid (the last one varies fastest) and of the columns.
AXES = ("freq_hz", "mass_ratio", "clearance", "contact_stiffness")

#: Result columns, from the summary attributes of ``DamperResult`` (all scalars).
RESULT_COLUMNS = ("primary_amplitude", "reduction", "impacts_per_cycle", "power_dissipated",
                  "is_steady", "steady_state_cycle", "amplitude_without_damper")

_CHUNKS_PER_WORKER = 8   # tasks per worker: load balance and progress granularity vs overhead


class SweepError(RuntimeError):
    """A combination of a :func:`sweep` failed; no partial table is returned.

    Attributes
    ----------
    combination : dict
        The swept values of the failed combination (``{axis: value}``), or of the first
        combination of the failed task when the executor itself failed it (then
        ``combinations`` lists all of that task's combinations).
    combinations : list of dict
        Every combination the failure concerns (one, unless the executor failed a task).

    The original exception is chained (``__cause__``); for a process pool its traceback in
    the worker is attached to it as a note.
    """

    def __init__(self, message, combinations):
        super().__init__(message)
        self.combinations = list(combinations)
        self.combination = self.combinations[0] if self.combinations else {}


# ----------------------------------------------------------------------------- validation
def _axis(name, values):
    """``values`` as a non-empty 1-D float array, finite, > 0 (``clearance``: >= 0)."""
    if np.isscalar(values) and not isinstance(values, (str, bytes)):
        values = [values]
    if isinstance(values, (str, bytes)):
        raise TypeError(f"{name} must be a 1-D sequence of numbers, got {values!r}")
    try:
        arr = np.asarray(values)
    except Exception as exc:  # ragged lists and the like
        raise TypeError(f"{name} must be a 1-D sequence of numbers, got {values!r}") from exc
    if arr.dtype == bool or not (np.issubdtype(arr.dtype, np.integer)
                                 or np.issubdtype(arr.dtype, np.floating)):
        raise TypeError(f"{name} must be a 1-D sequence of real numbers, got dtype "
                        f"{arr.dtype} from {values!r}")
    arr = arr.astype(float)
    if arr.ndim != 1:
        raise ValueError(f"{name} must be a 1-D sequence of values, got shape {arr.shape}")
    if arr.size == 0:
        raise ValueError(f"{name} must not be empty (give at least one value, or None "
                         "not to sweep it)")
    for value in arr:
        if not np.isfinite(value):
            raise ValueError(f"{name} must be finite, got {float(value)!r}")
        if name == "clearance" and value < 0.0:
            raise ValueError(f"clearance must be >= 0 (m, free travel on each side), got "
                             f"{float(value)!r}")
        if name != "clearance" and value <= 0.0:
            raise ValueError(f"{name} must be > 0, got {float(value)!r}")
    return arr


def _grid(axes):
    """List of ``{axis: value}`` over the Cartesian product (last axis fastest)."""
    names = list(axes)
    return [dict(zip(names, (float(v) for v in combo)))
            for combo in itertools.product(*(axes[name] for name in names))]


def _describe(combination):
    return ", ".join(f"{name}={value:.6g}" for name, value in combination.items()) or "(base)"


# ------------------------------------------------------------------------------ workers
def _changes(damper, combination):
    """The ``ImpactDamper.replace`` keywords of one combination."""
    changes = {}
    if "freq_hz" in combination:
        excitation = damper.excitation
        if dataclasses.is_dataclass(excitation):
            changes["excitation"] = dataclasses.replace(excitation,
                                                        freq_hz=combination["freq_hz"])
        else:
            changes["excitation"] = excitation.replace(freq_hz=combination["freq_hz"])
    if "mass_ratio" in combination:
        changes["damper_mass"] = combination["mass_ratio"] * float(damper.primary_mass)
    if "clearance" in combination:
        changes["clearance"] = combination["clearance"]
    if "contact_stiffness" in combination:
        changes["contact"] = dataclasses.replace(damper.contact,
                                                 stiffness=combination["contact_stiffness"])
    return changes


def _summary(result):
    """The small, picklable row of a ``DamperResult`` (floats, a bool, an int or None)."""
    cycle = result.steady_state_cycle
    return (float(result.primary_amplitude), float(result.reduction),
            float(result.impacts_per_cycle), float(result.power_dissipated),
            bool(result.is_steady), None if cycle is None else int(cycle),
            float(result.amplitude_without_damper))


def run_one(damper, combination, n_cycles):
    """Simulate one combination and return its summary row (a tuple, see ``RESULT_COLUMNS``)."""
    result = damper.replace(**_changes(damper, combination)).simulate(n_cycles)
    return _summary(result)


class _Failure:
    """What a task returns instead of rows when one of its combinations raised."""

    def __init__(self, position, exc):
        self.position = position
        try:  # the exception must cross a process boundary; some do not (un)pickle
            pickle.loads(pickle.dumps(exc))
        except Exception:  # noqa: BLE001 -- any failure to (un)pickle: send a stand-in
            exc = RuntimeError(f"{type(exc).__name__}: {exc} (the original exception "
                               "could not be pickled)")
        self.exc = exc


def _run_chunk(damper, items, n_cycles):
    """Task body: ``items`` = [(position, combination), ...] -> list of rows or _Failure."""
    rows = []
    for position, combination in items:
        try:
            rows.append(run_one(damper, combination, n_cycles))
        except Exception as exc:  # noqa: BLE001 -- reported by the caller, naming the case
            exc.add_note("traceback in the worker:\n" + traceback.format_exc())
            return _Failure(position, exc)
    return rows


# ----------------------------------------------------------------------------- progress
#: the bar: "sweep  40%|####      | 8/20 combinations [00:03<00:04]"
_BAR = ("{desc} {percentage:3.0f}%|{bar:30}| {n_fmt}/{total_fmt} combinations "
        "[{elapsed}<{remaining}]")


def _progress(total, enabled, stream=None, initial=0):
    """The sweep's tqdm bar on ``stream`` (stderr), counting combinations."""
    bar = progress_bar(total, enabled=enabled, desc="sweep", bar_format=_BAR, file=stream)
    if initial:
        bar.update(initial)
    return bar


def _run_items(damper, items, combinations, rows, n_cycles, executor, chunksize, store,
               bar):
    """Run ``items`` ([(position, combination)]) in tasks; fill ``rows``, the store, the bar."""
    with resolve_executor(executor) as pool:
        if chunksize is None:
            chunksize = max(1, math.ceil(len(items) / (_CHUNKS_PER_WORKER * pool.workers)))
        # strided, not contiguous: each task gets a spread of the grid (the cost of a run
        # varies strongly along an axis, e.g. near resonance), so no task is a straggler
        n_chunks = math.ceil(len(items) / chunksize)
        chunks = [items[i::n_chunks] for i in range(n_chunks)]
        tasks = [(damper, chunk, n_cycles) for chunk in chunks]
        with closing(pool.as_completed(_run_chunk, tasks)) as finished:
            for index, future in finished:
                chunk = chunks[index]
                try:
                    out = future.result()
                except Exception as exc:
                    cases = [c for _, c in chunk]
                    shown = "; ".join(_describe(c) for c in cases[:3])
                    more = f" and {len(cases) - 3} more" if len(cases) > 3 else ""
                    raise SweepError(
                        f"sweep: the executor failed the task of {len(cases)} "
                        f"combination(s) ({shown}{more}): {type(exc).__name__}: {exc}",
                        cases) from exc
                if isinstance(out, _Failure):
                    combination = combinations[out.position]
                    raise SweepError(
                        f"sweep: the combination {_describe(combination)} failed: "
                        f"{type(out.exc).__name__}: {out.exc}", [combination]) from out.exc
                if len(out) != len(chunk):
                    raise SweepError(f"sweep: a task returned {len(out)} rows for "
                                     f"{len(chunk)} combinations",
                                     [c for _, c in chunk])
                for (position, _), row in zip(chunk, out):
                    rows[position] = row
                if store is not None:
                    store.append([(combination, row)
                                  for (_, combination), row in zip(chunk, out)])
                bar.update(len(chunk))


def _check_phases(damper, combinations):
    """Fail early, in the caller's process, on a combination whose phases cannot be built
    (a frequency on an undamped mode of the primary, or of the primary with the mass stuck
    to it): one engine per design among ``combinations`` (those still to run), the
    clearance aside (it enters no phase's matrix). 6-40 ms a design on a 20-mode beam."""
    built = set()
    for combination in combinations:
        design = tuple(v for name, v in combination.items() if name != "clearance")
        if design in built:
            continue
        built.add(design)
        try:
            damper.replace(**_changes(damper, combination)).engine()
        except Exception as exc:
            raise SweepError(f"sweep: the combination {_describe(combination)} is invalid: "
                             f"{type(exc).__name__}: {exc}", [combination]) from exc


# -------------------------------------------------------------------------------- sweep
def sweep(damper, *, freq_hz=None, mass_ratio=None, clearance=None, contact_stiffness=None,
          n_cycles=200, executor=None, progress=False, chunksize=None, store=None):
    """Primary amplitude (and the rest of the summary) over a grid of damper designs.

    Every combination of the given axes (their Cartesian product) is simulated from rest
    with ``damper.replace(...)`` and :meth:`ImpactDamper.simulate`; the combinations run
    in parallel, several per task, and only each run's scalar summary comes back.

    Parameters
    ----------
    damper : ImpactDamper
        The base design; every value not swept is taken from it.
    freq_hz : array_like of float or None, keyword-only
        Excitation frequencies (Hz), finite, > 0: the excitation is copied with each
        frequency (amplitude and phase kept).
    mass_ratio : array_like of float or None, keyword-only
        ``damper_mass / damper.primary_mass``, finite, > 0.
    clearance : array_like of float or None, keyword-only
        Free travel on each side (m), finite, >= 0.
    contact_stiffness : array_like of float or None, keyword-only
        The contact law's ``stiffness`` (``LinearSpring``, ``Hertz``), finite, > 0; a
        ``ValueError`` if ``damper.contact`` has none (``Rigid``, ``InstantaneousImpact``).
    n_cycles : int, keyword-only
        Forcing cycles of each run (>= 1), from rest.
    executor : None, int, concurrent.futures.Executor or dask.distributed.Client, keyword-only
        Where the runs go (:func:`impactpred.parallel.resolve_executor`). ``None``: a
        ``ProcessPoolExecutor(max_workers=os.cpu_count())`` created and shut down inside
        this call; an integer ``n``: ``n`` processes so (1: in this process). Any
        ``Executor`` works: a ``ThreadPoolExecutor`` (no pickling, but the GIL serialises
        most of the work), a process pool of your own (reused across sweeps), a Dask
        ``Client`` or its ``client.get_executor()`` when one machine is not enough. A
        user executor or client is left running. The table does not depend on it.
    progress : bool, keyword-only
        Show a tqdm progress bar on stderr, counting combinations as tasks complete.
        Default False, as at every entry point of the library (the command lines turn
        it on).
    chunksize : int or None, keyword-only
        Combinations per task (at most). ``None``: about 8 tasks per worker (fewer,
        larger tasks cost less overhead; more, smaller ones balance the load and update
        the bar and the store more often). Each task takes every ``n_tasks``-th
        combination, so that expensive regions of the grid are shared out.
    store : str, os.PathLike or None, keyword-only
        A CSV file the sweep writes each finished row to, as its task comes back (flushed
        and synced), and resumes from: rows already there are not run again, and the
        table is bit-identical to an uninterrupted sweep's. Created when absent; a store
        written by another base damper, ``n_cycles`` or set of axes is refused. Format:
        :mod:`impactpred.damper._sweep_store` (``pandas.read_csv(store, comment="#")``
        reads it). A sweep interrupted by a kill, a failure or Ctrl-C loses only the
        tasks in flight.

    Returns
    -------
    pandas.DataFrame
        One row per combination, in grid order (``itertools.product`` of the axes in the
        order freq_hz, mass_ratio, clearance, contact_stiffness, the last varying fastest),
        every combination present. Columns: the swept axes, then ``primary_amplitude``
        (m), ``reduction``, ``impacts_per_cycle``, ``power_dissipated`` (W), ``is_steady``,
        ``steady_state_cycle`` (nullable integer), ``amplitude_without_damper`` (m). The
        ``attrs`` hold ``n_cycles`` and the base damper's ``repr``.

    Raises
    ------
    ValueError
        An axis that is empty, not 1-D, not finite or out of its domain (naming it and
        the value); no axis at all; ``contact_stiffness`` with a contact law without
        stiffness.
    SweepError
        A combination is invalid (the damper's ``replace`` refuses it, or its phases
        cannot be built: an excitation frequency on an undamped mode, of the primary or of
        the primary with the mass stuck to it), found before any run; or a combination
        failed (``simulate`` raised, or the executor failed its task): the message names
        the combination, the original exception is chained. Pending tasks
        are cancelled; no partial table is returned (with ``store``, the rows finished
        so far are in it, and a new call resumes from them).

    Notes
    -----
    Each task gets a pickled copy of ``damper`` (processes or Dask): keep the primary a
    model object, not something holding open files. With a process pool, pin BLAS to one
    thread per worker (``OPENBLAS_NUM_THREADS=1`` before Python starts): the engine's
    small matrix products are slower multi-threaded, and the workers already use every
    core. On one machine, :func:`impactpred.parallel.local_cluster` starts a Dask cluster
    set up for these runs. Workers started otherwise: without the
    ``MALLOC_TRIM_THRESHOLD_=65536`` Dask's nannies set by default (configuration
    ``distributed.nanny.pre-spawn-environ``) and with the profiler off
    (``distributed.worker.profile.enabled: false``): with Dask's defaults a damper run
    costs about 1.6 times the CPU (``benchmarks/bench_scaling.py``).

    Examples
    --------
    >>> table = sweep(damper, freq_hz=np.linspace(8, 12, 20),
    ...               clearance=np.geomspace(1e-4, 1e-2, 20))      # doctest: +SKIP
    >>> plot_optimum_clearance(table)                                # doctest: +SKIP

    On a Dask cluster, resumable::

        from dask.distributed import Client
        client = Client("scheduler-address:8786")
        table = sweep(damper, freq_hz=f, clearance=c, executor=client,
                      store="study.csv")
    """
    given = {name: value for name, value in zip(AXES, (freq_hz, mass_ratio, clearance,
                                                       contact_stiffness))
             if value is not None}
    if not given:
        raise ValueError("sweep needs at least one axis: freq_hz, mass_ratio, clearance or "
                         "contact_stiffness")
    axes = {name: _axis(name, value) for name, value in given.items()}
    n_cycles = as_count("n_cycles", n_cycles, minimum=1)
    if "contact_stiffness" in axes and not (
            dataclasses.is_dataclass(damper.contact)
            and any(f.name == "stiffness" for f in dataclasses.fields(damper.contact))):
        raise ValueError(f"contact_stiffness can only be swept for a contact law with a "
                         f"stiffness (LinearSpring, Hertz), got contact={damper.contact!r}")
    check_executor(executor)
    if store is not None and not isinstance(store, (str, os.PathLike)):
        raise TypeError(f"store must be a file path (str or os.PathLike) or None, got "
                        f"{store!r}")
    if chunksize is not None:
        chunksize = as_count("chunksize", chunksize, minimum=1)
    combinations = _grid(axes)
    # fail early, in the caller's process, on a combination replace() refuses
    for combination in combinations:
        try:
            damper.replace(**_changes(damper, combination))
        except Exception as exc:
            raise SweepError(f"sweep: the combination {_describe(combination)} is invalid: "
                             f"{type(exc).__name__}: {exc}", [combination]) from exc

    rows = [None] * len(combinations)
    store = None if store is None else SweepStore(
        store, axes=list(axes), result_columns=RESULT_COLUMNS, n_cycles=n_cycles,
        damper=damper)
    if store is not None:
        done = store.open()
        for position, combination in enumerate(combinations):
            rows[position] = done.get(tuple(combination.values()))
    items = [(position, combination) for position, combination in enumerate(combinations)
             if rows[position] is None]
    _check_phases(damper, [combination for _, combination in items])
    bar = _progress(len(combinations), bool(progress), initial=len(combinations) - len(items))
    try:
        if items:
            _run_items(damper, items, combinations, rows, n_cycles, executor, chunksize,
                       store, bar)
    finally:
        bar.close()

    missing = [combinations[i] for i, row in enumerate(rows) if row is None]
    if missing:  # cannot happen through the loop above; never return a table with holes
        raise SweepError(f"sweep: {len(missing)} combination(s) have no result, first: "
                         f"{_describe(missing[0])}", missing)
    table = pd.DataFrame([[c[name] for name in axes] for c in combinations],
                         columns=list(axes))
    results = pd.DataFrame(rows, columns=list(RESULT_COLUMNS))
    results["is_steady"] = results["is_steady"].astype(bool)
    results["steady_state_cycle"] = results["steady_state_cycle"].astype("Int64")
    table = pd.concat([table, results], axis=1)
    table.attrs.update({"n_cycles": n_cycles, "damper": repr(damper)})
    return table


# ------------------------------------------------------------------------------ optimum
def _x_axis(table, x):
    present = [name for name in AXES if name in table.columns and name != "clearance"]
    if x is not None:
        if x not in present:
            raise ValueError(f"x must be one of the table's swept columns {present}, got {x!r}")
        return x, [name for name in present if name != x]
    varying = [name for name in present if table[name].nunique() > 1]
    if not varying:
        raise ValueError("the table sweeps no axis besides clearance (freq_hz, mass_ratio "
                         "or contact_stiffness) to plot the optimum clearance against")
    x = varying[0]
    return x, [name for name in present if name != x]


def optimum_clearance(table, *, x=None):
    """The clearance minimising ``primary_amplitude``, for each value of the other axes.

    Parameters
    ----------
    table : pandas.DataFrame
        A :func:`sweep` table with a ``clearance`` column and at least one other axis.
    x : {"freq_hz", "mass_ratio", "contact_stiffness"} or None, keyword-only
        The axis to tabulate against; ``None``: the first of them that varies.

    Returns
    -------
    pandas.DataFrame
        One row per value of ``x`` (and of any other swept axis): those values, then
        ``clearance`` (the best of the grid), ``primary_amplitude``, ``reduction``,
        ``impacts_per_cycle`` and ``is_steady`` there, ``on_edge`` (True when the best
        clearance is the grid's smallest or largest: the true optimum may lie outside the
        grid) and ``damper_helps`` (False when no clearance of the grid lowers the
        amplitude with impacts: the damper idles at the best clearance, and ``clearance``
        is then the smallest of the grid without impacts, the edge of the idle range;
        a :class:`UserWarning` names those rows). Rows whose amplitudes are all NaN are
        left out.
    """
    best, axes = _optimum_rows(table, x)
    _warn_unhelpful(best, axes)
    return best


def _optimum_rows(table, x):
    """:func:`optimum_clearance`'s table, without its warning, and the axes it keys on."""
    if not isinstance(table, pd.DataFrame):
        raise TypeError(f"table must be a pandas DataFrame from sweep(), got "
                        f"{type(table).__name__}")
    for column in ("clearance", "primary_amplitude"):
        if column not in table.columns:
            raise ValueError(f"table has no {column!r} column (columns: {list(table.columns)})")
    x, others = _x_axis(table, x)
    lo, hi = table["clearance"].min(), table["clearance"].max()
    rows = []
    for key, group in table.groupby([x] + others, sort=True):
        amplitude = group["primary_amplitude"]
        if amplitude.notna().sum() == 0:
            continue
        best = group.loc[amplitude.idxmin()]
        helps = _damper_helps(best)
        if not helps and best.get("impacts_per_cycle", np.nan) == 0:
            # an idle damper: the impact-free clearances tie (to the transient's remnant);
            # report the smallest, where the idle range starts
            idle = group[(group["impacts_per_cycle"] == 0)
                         & (group["primary_amplitude"] <= best["primary_amplitude"]
                            * (1.0 + 1e-6))]
            best = idle.loc[idle["clearance"].idxmin()]
        key = key if isinstance(key, tuple) else (key,)
        row = dict(zip([x] + others, key))
        row.update({"clearance": best["clearance"],
                    "primary_amplitude": best["primary_amplitude"],
                    "reduction": best.get("reduction", np.nan),
                    "impacts_per_cycle": best.get("impacts_per_cycle", np.nan),
                    "is_steady": bool(best.get("is_steady", True)),
                    "on_edge": bool(group["clearance"].nunique() > 1
                                    and best["clearance"] in (lo, hi)),
                    "damper_helps": helps})
        rows.append(row)
    result = pd.DataFrame(rows, columns=[x] + others + [
        "clearance", "primary_amplitude", "reduction", "impacts_per_cycle", "is_steady",
        "on_edge", "damper_helps"])
    return result, [x] + others


def _damper_helps(best):
    """Whether the best row lowers the amplitude (its ``reduction`` under 1) with impacts;
    without a reduction (a free rattle), whether it impacts."""
    impacts = best.get("impacts_per_cycle", np.nan)
    reduction = best.get("reduction", np.nan)
    if impacts == 0:
        return False
    return not (np.isfinite(reduction) and reduction >= 1.0 - 1e-6)


def _warn_unhelpful(best, axes, stacklevel=3):
    """One UserWarning for the rows of ``best`` where no clearance of the grid helps:
    those where the damper idles (the best clearance has no impacts) and those where
    every clearance impacts and raises the amplitude."""
    unhelpful = best[~best["damper_helps"]]
    if not len(unhelpful):
        return
    idle = unhelpful["impacts_per_cycle"] == 0

    def where(rows):
        text = "; ".join(", ".join(f"{a}={row[a]:.6g}" for a in axes)
                         for _, row in rows.head(5).iterrows())
        return text + (f" and {len(rows) - 5} more" if len(rows) > 5 else "")

    parts = []
    if idle.any():
        parts.append(f"at {where(unhelpful[idle])} the best clearance of the grid has no "
                     f"impacts: the damper idles there, and every impacting clearance "
                     f"raises the amplitude")
    if (~idle).any():
        parts.append(f"at {where(unhelpful[~idle])} every clearance of the grid impacts "
                     f"and raises the amplitude (larger ones may let the damper idle)")
    warnings.warn("optimum_clearance: no clearance of the grid lowers the primary amplitude "
                  "(damper_helps=False): " + "; ".join(parts) + "; another mass ratio or "
                  "frequency may help", UserWarning, stacklevel=stacklevel)


_LABELS = {"freq_hz": "excitation frequency (Hz)", "mass_ratio": "mass ratio",
           "contact_stiffness": "contact stiffness"}


def plot_optimum_clearance(table, *, ax=None, x=None):
    """Plot the clearance minimising the primary amplitude against frequency (or mass ratio).

    Parameters
    ----------
    table : pandas.DataFrame
        A :func:`sweep` table with a ``clearance`` column and at least one other axis.
    ax : matplotlib.axes.Axes or None, keyword-only
        Where to draw; ``None``: a new figure.
    x : {"freq_hz", "mass_ratio", "contact_stiffness"} or None, keyword-only
        The abscissa; ``None``: ``freq_hz`` if it varies, else ``mass_ratio``, else
        ``contact_stiffness``. Any other swept axis gives one line per value.

    Returns
    -------
    matplotlib.axes.Axes
        Optimum clearance (mm) per ``x``; open markers where the optimum is at the edge
        of the swept clearances (widen the grid there) or the run was not steady, crosses
        where no clearance of the grid helps (the damper idles; see
        :func:`optimum_clearance`, which also warns). The reduction at the optimum is on a
        twin axis (dashed).
    """
    best, axes = _optimum_rows(table, x)
    _warn_unhelpful(best, axes)
    x = best.columns[0]
    others = [c for c in best.columns[1:] if c in AXES and c != "clearance"]
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots()
    twin = ax.twinx()
    crossed = False
    groups = best.groupby(others, sort=True) if others else [((), best)]
    for key, group in groups:
        key = key if isinstance(key, tuple) else (key,)
        label = ", ".join(f"{name}={value:.4g}" for name, value in zip(others, key))
        line, = ax.plot(group[x], 1e3 * group["clearance"], "-o", label=label or
                        "optimum clearance")
        doubtful = group["on_edge"] | ~group["is_steady"]
        if doubtful.any():
            ax.plot(group[x][doubtful], 1e3 * group["clearance"][doubtful], "o",
                    markerfacecolor="white", color=line.get_color())
        idle = ~group["damper_helps"]
        if idle.any():
            ax.plot(group[x][idle], 1e3 * group["clearance"][idle], "x", markersize=10,
                    color=line.get_color(),
                    label="_" if crossed else "no clearance of the grid helps")
            crossed = True
        twin.plot(group[x], group["reduction"], "--", color=line.get_color(), alpha=0.6)
    ax.set_xlabel(_LABELS.get(x, x))
    ax.set_ylabel("optimum clearance (mm)")
    twin.set_ylabel("amplitude reduction at the optimum (dashed)")
    ax.set_title("clearance minimising the primary amplitude")
    ax.legend(loc="best")
    return ax
