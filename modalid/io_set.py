"""Reading a set of FRFs (one driving point, several outputs) as one :class:`FRFSet`.

:func:`read_frf_set` takes one UFF file with several dataset-58 records, several files
(any format :func:`modalid.io.read_frfs` reads, or bare complex lines with ``freq_hz=``),
or one CSV table with several FRF columns. The rows must share one frequency grid: sets on
different grids are refused with the files and lines that differ, never resampled. Which
row is the driving point comes from the UFF records (the response at the reference's node
and axis) or from ``driving_point=``; a set without one is read only with
``driving_point=None``.
"""

from __future__ import annotations

import os
import re
import warnings

from ._io_records import _QUANTITY_WORDS, _UNITS, _WORDS, _build, split_unit
from .frf_set import FRFSet, grid_difference
from ._uff import at_reference
from .io import (_check_orientation, _load_table, _oriented, _read_raw, _read_table, _resolve,
                 read_complex_lines)

__all__ = ["read_frf_set"]

_ROLE_WORDS = (set().union(*_WORDS.values()) | set(_UNITS) | set(_QUANTITY_WORDS) | {"s"}) - {""}
_DIRECTIONS = {1: "+X", 2: "+Y", 3: "+Z", 4: "+RX", 5: "+RY", 6: "+RZ", -1: "-X", -2: "-Y",
               -3: "-Z", -4: "-RX", -5: "-RY", -6: "-RZ"}


def _split_label(name):
    """``(label, role_name)`` of a CSV column of a multi-FRF table: the words that name a
    role or unit (``real``, ``phase``, ``deg``, ``[Hz]``...) and the rest, the label of the
    output (``"p2 real"`` -> ``("p2", "real")``, ``"mag_db_3"`` -> ``("3", "mag_db")``)."""
    base, stated = split_unit(name)
    unit = "" if stated is None else f" [{stated}]"
    tokens = [t for t in re.split(r"[^A-Za-z0-9]+", base) if t]
    label = "_".join(t for t in tokens if t.lower() not in _ROLE_WORDS)
    return label, "_".join(t for t in tokens if t.lower() in _ROLE_WORDS) + unit


def _table_set(path, columns):
    """Raw FRFs and labels of a CSV with one frequency column and several FRF groups."""
    table, stated, measured = _load_table(path)
    groups = {}
    for name in table.columns:
        label, role = _split_label(name)
        groups.setdefault(label, []).append((name, role))
    outputs = [g for g in groups if g != ""]
    if len(outputs) <= 1:                           # one FRF: the single-FRF rules
        return (_read_table(path, columns, table, stated, measured),
                [outputs[0] if outputs else path.stem])
    freq = [n for n, _ in groups.get("", [])]
    if len(freq) != 1:
        raise ValueError(f"{path} holds the FRF column groups {outputs} and needs exactly one "
                         f"frequency column without a label, found {freq}")
    raws = []
    for label in outputs:
        names = {name: role for name, role in groups[label]}
        sub = table[freq + list(names)].rename(columns=names)
        raws += _read_table(f"{path} (output {label!r}: columns {list(names)})", None, sub,
                            stated)
    return raws, outputs


def _dof_label(node, direction):
    return f"{node}{_DIRECTIONS.get(direction, f':{direction}')}"


def _uff_labels(metas):
    """Labels from the UFF DOFs along positive directions (the values are read so): the
    roving one (response or reference), else both."""
    rsp = [_dof_label(m["response_node"], abs(m["response_dir"])) for m in metas]
    ref = [_dof_label(m["reference_node"], abs(m["reference_dir"])) for m in metas]
    if len(set(ref)) == 1 and len(set(rsp)) == len(rsp):
        return rsp
    if len(set(rsp)) == 1 and len(set(ref)) == len(ref):
        return ref
    return [f"{a}/{b}" for a, b in zip(rsp, ref)]


def _unique(labels):
    seen = {}
    out = []
    for label in labels:
        seen[label] = seen.get(label, 0) + 1
        out.append(label if labels.count(label) == 1 else f"{label}[{seen[label] - 1}]")
    return out


def read_frf_set(path_or_paths, *, driving_point="auto", format=None, quantity=None,
                 columns=None, outputs=None, freq_hz=None, conjugate=False,
                 negate=False) -> FRFSet:
    """Read several FRFs of one input as one :class:`FRFSet`.

    Parameters
    ----------
    path_or_paths : str, os.PathLike or sequence of them
        One file holding several FRFs (UFF with several dataset-58 records, a CSV table
        with several FRF column groups, a .mat analyzer export with several channels), or
        several files (each holding one FRF or more), read in the order given.
    driving_point : "auto", int, str or None
        The driving-point row (index or output label). ``"auto"``: the UFF record whose
        response is at its reference's node and axis (a record along the opposite
        direction is read negated: :func:`modalid.io.read_frfs`); other formats do not
        say, so ``"auto"``
        raises asking for it. ``None``: no row is the driving point (the set can be
        plotted and converted but not fitted).
    format, quantity, columns
        As :func:`modalid.io.read_frfs`, for every file; ``format="complex-lines"``
        with ``freq_hz`` for bare complex lines (:func:`modalid.io.read_complex_lines`).
        In a multi-FRF CSV, columns are grouped by the words that are not role or unit
        words: ``freq_hz, p1_real, p1_imag, p2_real, p2_imag`` gives outputs ``p1`` and
        ``p2`` (``mag_db_1, phase_deg_1, coh_1`` ... likewise); ``columns`` applies to
        single-FRF files only.
    outputs : sequence of str, optional
        Row labels; default from the UFF DOFs along positive directions, as the values
        are read (the roving one: response node and direction, e.g. ``"3+Z"``, when the
        reference is fixed), the CSV column groups, or the file names.
    freq_hz : array_like of float, optional
        Frequencies (Hz) of bare complex-lines files.
    conjugate, negate : bool, default False
        As :func:`modalid.io.read_frf`, for every FRF read (a file convention, or a
        response direction, that all the rows share).

    Returns
    -------
    FRFSet

    Raises
    ------
    ValueError
        Rows on different frequency grids (naming the files and how the grids differ),
        of different quantities, no driving point found for ``"auto"`` (or several), an
        output index or label out of range, non-finite values.
    """
    _check_orientation(conjugate, negate)
    single = isinstance(path_or_paths, (str, os.PathLike))
    if not single and not hasattr(path_or_paths, "__iter__"):
        raise TypeError(f"path_or_paths must be a path or a list of paths, got "
                        f"{type(path_or_paths).__name__}")
    paths = [path_or_paths] if single else list(path_or_paths)
    if not paths:
        raise ValueError("path_or_paths must name at least one file, got an empty sequence")
    frfs, labels, sources, metas = [], [], [], []
    for given in paths:
        path, fmt = _resolve(given, format)
        if fmt == "complex-lines" or freq_hz is not None:
            if freq_hz is None:
                raise ValueError(f"{path} holds bare complex values: pass freq_hz= (Hz, one "
                                 "per value line)")
            raws, names = None, [path.stem]
            frfs.append(read_complex_lines(path, freq_hz=freq_hz, quantity=quantity))
        else:
            if fmt == "csv":
                raws, names = _table_set(path, columns)
            else:
                raws = _read_raw(path, fmt, columns)
                names = [path.stem + (f"[{k}]" if len(raws) > 1 else "")
                         for k in range(len(raws))]
            for k, raw in enumerate(raws):
                frfs.append(_build(f"{path}" + (f" (FRF {k})" if len(raws) > 1 else ""), raw,
                                   quantity))
        metas += [r.meta for r in raws] if raws else [{}]
        sources += [f"{path}" + (f" (FRF {k})" if len(names) > 1 else "")
                    for k in range(len(names))]
        labels += names
    frfs = [_oriented(frf, conjugate, negate) for frf in frfs]
    for i, frf in enumerate(frfs[1:], start=1):
        if frf.quantity != frfs[0].quantity:
            raise ValueError(f"{sources[i]} is {frf.quantity}, {sources[0]} is "
                             f"{frfs[0].quantity}: one set holds one quantity")
        why = grid_difference(frfs[0].freq_hz, frf.freq_hz)
        if why:
            raise ValueError(f"{sources[0]} and {sources[i]} are on different frequency "
                             f"grids: {why}. An FRFSet needs one grid: resample or cut the "
                             "FRFs yourself; nothing is interpolated")
    uff = all("response_node" in m for m in metas)
    if outputs is None:
        outputs = _unique(_uff_labels(metas) if uff else labels)
    if isinstance(driving_point, str) and driving_point == "auto":
        driving_point = _auto_driving_point(metas, uff, sources)
    return FRFSet.from_frfs(frfs, driving_point=driving_point, outputs=outputs)


def _auto_driving_point(metas, uff, sources):
    if not uff:
        raise ValueError("these files do not say which FRF is the driving point (only UFF "
                         "records do, by their DOFs): pass driving_point= the row index or "
                         "output label of the FRF measured at the excitation point, or "
                         "driving_point=None if there is none")
    # the reader took every record to positive directions (a response along -Z at the
    # reference node +Z, negated, is the driving point)
    same = [i for i, m in enumerate(metas) if at_reference(m)]
    if len(same) != 1:
        dofs = [f"{_dof_label(m['response_node'], m['response_dir'])}/"
                f"{_dof_label(m['reference_node'], m['reference_dir'])}" for m in metas]
        found = "no record has" if not same else f"records {same} have"
        raise ValueError(f"no single driving point among {sources}: {found} its response at "
                         f"its reference's node and axis (response/reference: {dofs}); pass "
                         "driving_point= a row index or label, or None")
    return same[0]


def uff_record(path, options) -> dict | None:
    """The metadata of the UFF record of ``path`` that ``read_frf(path, **options)`` reads
    (:func:`modalid.io.describe_frfs`'s columns but the quantity and band: its DOFs as
    stored, ``negated``, ``to_si``), or None for another kind of file. The file's warnings
    are not said again (they were when it was read)."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            where, fmt = _resolve(path, options.get("format"))
            raws = _read_raw(where, fmt, options.get("columns"))
    except (ValueError, OSError):       # bare complex lines: no records to describe
        return None
    meta = raws[options.get("index") or 0].meta
    return meta if "response_node" in meta else None
