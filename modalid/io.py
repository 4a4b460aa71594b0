"""Reading and writing measured FRFs: CSV, NumPy ``.npz``, MATLAB ``.mat`` and UFF 58.

One file holds one FRF or several; the rule is the same for every format:

* :func:`read_frfs` returns every FRF in the file, as a list of :class:`FRFData`;
* :func:`read_frf` returns one :class:`FRFData`: the only one, or the one ``index=``
  picks; a file holding several without ``index=`` is a ``ValueError``;
* :func:`describe_frfs` tabulates what :func:`read_frfs` would return (quantity,
  lines, band, UFF response/reference node and direction), for choosing ``index``;
* :func:`check_sign` tells an FRF stored with the other sign convention (the complex
  conjugate) or a driving point with its sign reversed; ``read_frf(...,
  conjugate=True)`` / ``negate=True`` read them right.

The quantity (receptance, mobility or accelerance) comes from the file when it says it,
else from ``quantity=``, else reading fails asking for it; a file and an argument that
disagree are an error, never silently resolved. Values are taken in SI units of the
quantity unless a table's column header states another (``real [mm/N]``, ``f [kHz]``:
converted; a unit not known is refused); frequencies are converted to Hz.

Nothing read is executed: ``.npz`` is opened with ``allow_pickle=False``, complex text
lines are parsed by :class:`complex`, never ``eval``.

Here: the public functions, the CSV, NPZ and MAT readers; their common ground (names to
roles, records to :class:`FRFData`) in :mod:`modalid._io_records`, UFF in :mod:`._uff`.
"""

from __future__ import annotations

import os
import re
import struct
import zipfile
from pathlib import Path

import numpy as np

from ._checks import as_choice, as_count, as_real_array, one_of
from ._io_records import (
    _QUANTITY_WORDS,
    ARRAY_HELP,
    ARRAY_ROLES,
    TABLE_HELP,
    TABLE_ROLES,
    _assign_roles,
    _build,
    _column_role,
    _finite,
    _Raw,
    _decoded_text,
    _text_head,
    _vector,
    header_unit,
    quantity_in_comment,
    same_unit,
    unit_factor,
)
from ._io_measured import comment_lines, stated_in_arrays, stated_in_comment, statements
from ._sign import SignCheck, check_sign
from ._uff import _dof, _read_uff, _write_uff, records_listing
from .frf import FRFData
from .quantities import QUANTITIES

__all__ = ["read_frf", "read_frfs", "write_frf", "describe_frfs", "read_complex_lines",
           "check_sign", "SignCheck"]

READ_FORMATS = ("csv", "npz", "mat", "uff", "complex-lines")
WRITE_FORMATS = ("csv", "npz", "mat", "uff")
_EXTENSIONS = {".csv": "csv", ".tsv": "csv", ".txt": "text", ".npz": "npz", ".mat": "mat",
               ".uff": "uff", ".unv": "uff", ".uf": "uff"}


# ------------------------------------------------------------------ CSV / text
def _load_table(path):
    """``(table, stated, measured)``: a table (str column names), the quantities its
    comments state, and how the FRF was measured (:mod:`modalid._io_measured`)."""
    import pandas as pd

    text, encoding = _decoded_text(path)
    lines = text.splitlines()
    lead, stated, measured = 0, set(), {}
    for line in lines:
        if line.strip() and not line.lstrip().startswith("#"):
            break
        lead += 1
        said = stated_in_comment(path, line)
        if said is not None:
            measured[said[0]] = said[1]
        stated |= quantity_in_comment(path, line)
    if lead == len(lines):
        raise ValueError(f"{path} holds no table: no header line after its comments")
    sep = next((s for s in (",", ";", "\t") if s in lines[lead]), r"\s+")
    header = {}
    try:  # numbers first: the header is the last comment line, as np.savetxt writes it
        [float(t) for t in re.split(sep, lines[lead].strip())]
        if lead:
            text = lines[lead - 1].lstrip().lstrip("#").strip()
            header = {"header": None, "names": [t.strip() for t in re.split(sep, text)]}
    except ValueError:
        pass
    # pandas >= 3 parses floats exactly by default and deprecates float_precision
    exact = {"float_precision": "round_trip"} if int(pd.__version__.split(".")[0]) < 3 else {}
    try:
        table = pd.read_csv(path, sep=sep, skiprows=lead, comment="#", encoding=encoding,
                            skipinitialspace=True, **header, **exact)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise ValueError(f"cannot parse {path} as a table: {exc}") from exc
    table.columns = [str(c) for c in table.columns]
    return table, stated, measured


def _read_table(path, columns, table=None, stated=None, measured=None):
    """The raw FRF of a table file (or of ``table``, already loaded, for ``path``, with
    the quantities and measurement its comments state)."""
    import pandas as pd

    table, stated, measured = (_load_table(path) if table is None
                               else (table, set(stated), measured or {}))
    names = list(table.columns)
    found = _assign_roles(names, TABLE_ROLES, columns, str(path))

    def column(role):
        name = found[role][0]
        values = pd.to_numeric(table[name], errors="coerce").to_numpy(dtype=float)
        # -inf dB is a zero magnitude (an analyzer's 0 Hz line)
        bad = ~np.isfinite(values) & ((values != -np.inf) | (role != "magnitude_db"))
        if np.any(bad):
            i = int(np.argmax(bad))
            value = table[name].iloc[i]
            value = value.item() if isinstance(value, np.generic) else value
            comma = (": a decimal comma? this reader takes decimal points (pandas.read_csv("
                     "..., sep=';', decimal=',') reads it; give FRFData its columns)"
                     if isinstance(value, str) and re.fullmatch(r"[-+]?\d*,\d+", value.strip())
                     else "")
            raise ValueError(f"column {name!r} of {path} has a missing, non-numeric or "
                             f"non-finite value at data row {i + 1}: {value!r}{comma}")
        unit = header_unit(name)
        if unit is None:
            return values
        factor, quantity = unit_factor(path, name, role, unit)
        if quantity is not None:
            stated.add(quantity)
        return values + 20.0 * np.log10(factor) if role == "magnitude_db" else values * factor

    freq_role = [r for r in ("freq_hz", "omega_rad_s") if r in found]
    if len(freq_role) != 1:
        raise ValueError(f"{path} needs exactly one frequency column, found "
                         f"{[found[r][0] for r in freq_role]} among {names}; " + TABLE_HELP)
    freq = column(freq_role[0]) / (2 * np.pi if freq_role[0] == "omega_rad_s" else 1.0)
    mags = [r for r in ("magnitude", "magnitude_db") if r in found]
    phases = [r for r in ("phase_deg", "phase_rad") if r in found]
    if "real" in found and "imag" in found:
        same_unit(path, found["real"][0], found["imag"][0])
        used, values = ["real", "imag"], column("real") + 1j * column("imag")
    elif len(mags) == 1 and len(phases) == 1:
        used, (mag, phase) = mags + phases, (column(mags[0]), column(phases[0]))
        mag = 10.0 ** (mag / 20.0) if mags[0] == "magnitude_db" else mag
        values = mag * np.exp(1j * (np.radians(phase) if phases[0] == "phase_deg" else phase))
    else:
        hint = ("; a phase column must say its unit (phase_deg or phase_rad)"
                if any(_column_role(n)[0] == "phase" for n in names) else "")
        raise ValueError(f"{path} has no real/imag pair nor one magnitude + one phase column "
                         f"among {names}{hint}; " + TABLE_HELP)
    stated |= {found[r][1] for r in used + freq_role if found[r][1] is not None}
    if len(stated) > 1:
        raise ValueError(f"{path} names several quantities: {sorted(stated)}")
    coherence = column("coherence") if "coherence" in found else None
    excitation = column("excitation") if "excitation" in found else None
    return [_Raw(freq, values, coherence, stated.pop() if stated else None,
                 (found[freq_role[0]][0], "/".join(found[r][0] for r in used),
                  found.get("coherence", ("coherence",))[0]), excitation=excitation,
                 measured=measured)]


def _is_complex_lines(path):
    with open(path, encoding="utf-8-sig", errors="replace") as fh:
        for line in fh:
            if line.strip() and not line.lstrip().startswith("#"):
                return bool(re.fullmatch(r"\s*\(?[-+0-9.eEinfa]+j\)?\s*", line))
    return False


def read_complex_lines(path, *, freq_hz, quantity) -> FRFData:
    """One FRF stored as one Python complex literal per line, e.g. ``(-0.0775+2.7e-08j)``.

    Lines are parsed by :class:`complex` (never ``eval``); blank lines and ``#`` comments
    are skipped. The file holds no frequencies: ``freq_hz`` gives one per value line
    (for the pyuff beam files, line k is k Hz: ``freq_hz=np.arange(1001)``).

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    freq_hz : array_like of float, keyword-only
        One frequency (Hz) per value line.
    quantity : {"receptance", "mobility", "accelerance"}, keyword-only
        What the values are.

    Returns
    -------
    FRFData
    """
    path = _as_path(path)
    freq_hz = as_real_array("freq_hz", freq_hz, ndim=1)
    values = []
    for number, line in enumerate(_decoded_text(path)[0].splitlines(), start=1):
        text = line.strip()
        if not text or text.startswith("#"):
            continue
        try:
            values.append(complex(text.replace(" ", "")))
        except ValueError:
            raise ValueError(f"line {number} of {path} is not a complex number: "
                             f"{text[:60]!r}") from None
    values = _finite(str(path), "the values", np.array(values, dtype=complex))
    if values.size != freq_hz.size:
        raise ValueError(f"{path} holds {values.size} values but freq_hz has {freq_hz.size}")
    return _build(str(path), _Raw(freq_hz, values, None, None, ("freq_hz", "values", "")),
                  quantity)


# ------------------------------------------------------------------ NPZ / MAT
def _from_arrays(source, arrays, columns):
    """One raw FRF from named arrays (npz, or a simple .mat layout)."""
    found = _assign_roles(list(arrays), ARRAY_ROLES, columns, source)
    freq_role = [r for r in ("freq_hz", "omega_rad_s") if r in found]
    if len(freq_role) != 1 or "values" not in found:
        raise ValueError(f"{source} needs one frequency and one values variable, it has "
                         f"{sorted(arrays)}; " + ARRAY_HELP
                         + "; or pass columns={'freq_hz': ..., 'values': ...}")
    f_name, v_name = found[freq_role[0]][0], found["values"][0]
    freq = _vector(source, f_name, arrays[f_name])      # real: checked by _build
    if freq_role[0] == "omega_rad_s":
        freq = freq / (2 * np.pi)
    values = _vector(source, v_name, arrays[v_name])
    c_name = found.get("coherence", ("coherence",))[0]
    coherence = _vector(source, c_name, arrays[c_name]) if "coherence" in found else None
    e_name = found.get("excitation", ("excitation",))[0]
    excitation = _vector(source, e_name, arrays[e_name]) if "excitation" in found else None
    stated = found["values"][1]
    if "quantity" in found:
        q = np.asarray(arrays[found["quantity"][0]])
        text = str(q.ravel()[0]).strip().lower() if q.dtype.kind in "US" and q.size else None
        if text not in _QUANTITY_WORDS:
            raise ValueError(f"variable {found['quantity'][0]!r} of {source} must name one "
                             f"of {list(QUANTITIES)}, got {q!r}")
        if stated is not None and stated != _QUANTITY_WORDS[text]:
            raise ValueError(f"{source} names two quantities: {stated} and {text}")
        stated = _QUANTITY_WORDS[text]
    return _Raw(freq, values, coherence, stated, (f_name, v_name, c_name),
                excitation=excitation, measured=stated_in_arrays(source, arrays))


#: how an .npz (a zip archive) and an .npy file begin; what a single .npy array may be
_NPZ_MAGIC, _NPY_MAGIC = b"PK\x03\x04", b"\x93NUMPY"
_NPY_HINT = ("; if it holds a hammer test's records (rows time, force and response), "
             "make the FRF from them with modalid.frf_from_hammer")


def _read_npz(path, columns):
    with open(path, "rb") as fh:
        magic = fh.read(6)
    if magic.startswith(_NPY_MAGIC):
        raise ValueError(f"cannot read {path} as .npz: it holds a single .npy array, not an "
                         ".npz archive (save the FRF with numpy.savez)" + _NPY_HINT)
    if not magic.startswith(_NPZ_MAGIC):
        head = _text_head(path)
        start = ("it is empty" if not magic else f"it starts {head!r}" if head is not None
                 else f"it starts {magic!r}")
        raise ValueError(f"{path} is not an .npz archive ({start}; an .npz is a zip file "
                         "written by numpy.savez)")
    try:
        archive = np.load(path, allow_pickle=False)
        with archive:
            arrays = {key: archive[key] for key in archive.files}
    except ValueError as exc:
        raise ValueError(f"cannot read {path} as .npz (pickled/object arrays are refused): "
                         f"{exc}") from exc
    except (OSError, EOFError, zipfile.BadZipFile) as exc:
        raise ValueError(f"{path} is not a readable .npz archive (truncated or damaged?): "
                         f"{exc}") from exc
    return [_from_arrays(str(path), arrays, columns)]


def _read_mat(path, columns):
    import scipy.io

    head = _text_head(path)
    if head is not None:
        raise ValueError(f"{path} is a text file, not a MATLAB file (it starts {head!r}): "
                         "rename it .csv or .txt, or pass format='csv'")
    try:
        data = scipy.io.loadmat(path)
    except NotImplementedError as exc:
        raise ValueError(f"{path} is a MATLAB v7.3 (HDF5) file, not supported: save it with "
                         "-v7 or -v6") from exc
    except (ValueError, TypeError, OSError, IndexError, KeyError, EOFError, struct.error,
            scipy.io.matlab.MatReadError) as exc:   # scipy's own errors on a damaged file
        raise ValueError(f"{path} is not a readable MATLAB file: {type(exc).__name__}: "
                         f"{exc}") from exc
    arrays = {k: v for k, v in data.items() if not k.startswith("__")}
    channels = sorted((int(m.group(1)), k) for k in arrays
                      if (m := re.fullmatch(r"Hf_chan_(\d+)", k)))
    if columns is not None or not channels or "Freq_domain" not in arrays:
        return [_from_arrays(str(path), arrays, columns)]
    raws = []   # analyzer export: Freq_domain, Hf_chan_N (chan N over chan 1), Hf_coh_chan_N
    for number, key in channels:
        names = {"freq_hz": "Freq_domain", "values": key}
        if f"Hf_coh_chan_{number}" in arrays:
            names["coherence"] = f"Hf_coh_chan_{number}"
        raw = _from_arrays(str(path), {v: arrays[v] for v in names.values()}, names)
        raw.meta = {"response_channel": number, "reference_channel": 1}
        raws.append(raw)
    return raws


# ------------------------------------------------------------------ public API
def _as_path(path):
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path must be a str or os.PathLike, got {type(path).__name__}")
    return Path(path)


def _format_of(path, fmt, choices):
    """The format named by ``fmt`` or the extension; "text" (.txt) is sniffed on reading."""
    if fmt is not None:
        return as_choice("format", fmt.lower() if isinstance(fmt, str) else fmt, choices)
    ext = path.suffix.lower()
    known = set(choices) | ({"text"} if "complex-lines" in choices else set())
    accepted = [e for e, f in _EXTENSIONS.items() if f in known]
    if _EXTENSIONS.get(ext) not in known:
        raise ValueError(f"cannot tell the format of {str(path)!r} from its extension "
                         f"{ext!r}: accepted extensions are {one_of(accepted)}, or pass "
                         f"format= one of {one_of(choices)}" + _NPY_HINT * (ext == ".npy"))
    return _EXTENSIONS[ext]


def _resolve(path, fmt):
    """``(Path, format)`` of an existing file; a .txt file is sniffed."""
    path = _as_path(path)
    fmt = _format_of(path, fmt, READ_FORMATS)
    if not path.is_file():
        raise FileNotFoundError(f"no such file: {str(path)!r}")
    if fmt == "text":
        fmt = "complex-lines" if _is_complex_lines(path) else "csv"
    return path, fmt


def _read_raw(path, fmt, columns):
    if columns is not None and fmt not in ("csv", "npz", "mat"):
        raise ValueError(f"columns= applies to CSV, NPZ and MAT files, not to {fmt}")
    if fmt == "complex-lines":
        raise ValueError(f"{path} holds bare complex values (no frequencies): read it with "
                         "read_frf(path, format='complex-lines', freq_hz=..., quantity=...)")
    readers = {"csv": _read_table, "npz": _read_npz, "mat": _read_mat, "uff": _read_uff}
    return readers[fmt](path, columns)


def _read_all(path, fmt, quantity, columns):
    raws, frfs = _read_raw(path, fmt, columns), []
    for i, raw in enumerate(raws):  # a loop, not a comprehension: warnings' stacklevel
        frfs.append(_build(f"{path}" + (f" (FRF {i})" if len(raws) > 1 else ""), raw, quantity))
    return frfs


def read_frfs(path, *, format=None, quantity=None, columns=None) -> list[FRFData]:
    """Every FRF in a file, in file order.

    Parameters
    ----------
    path : str or os.PathLike
    format : {"csv", "npz", "mat", "uff"}, optional
        Default: from the extension: .csv/.tsv, .npz, .mat, .uff/.unv/.uf, and .txt (a
        table, or complex lines when its first line is a complex literal: see
        :func:`read_frf`).
    quantity : {"receptance", "mobility", "accelerance"}, optional
        Needed when the file does not say it; an error if the file says otherwise.
    columns : dict, optional
        Role -> column (CSV) or variable (NPZ/MAT) name, overriding name detection.
        CSV roles: freq_hz | omega_rad_s, real + imag or magnitude | magnitude_db +
        phase_deg | phase_rad, coherence, excitation. NPZ/MAT roles: freq_hz | omega_rad_s,
        values, coherence, excitation, quantity.

    Returns
    -------
    list of FRFData

    Notes
    -----
    *CSV*: leading ``#`` lines may say ``# quantity: accelerance``; the header is the
    first other line, or the last ``#`` line when numbers follow it (``np.savetxt``'s
    ``header=``). Header names are matched case-insensitively, words split on any
    punctuation, a trailing ``[unit]`` or ``(unit)`` read as below: frequency ``f``,
    ``freq``, ``frequency`` (Hz unless rad/s is said), ``omega``/``w`` (rad/s); ``re``/``real`` and
    ``im``/``imag``; ``mag``/``magnitude``/``abs``/``amplitude`` (linear, or dB =
    ``20 log10 |H|`` when the name says dB) with ``phase``/``arg``/``angle`` + ``deg`` or
    ``rad`` (a phase without unit is refused); ``coh``/``coherence``;
    ``excitation``/``force_spectrum`` (the excitation's autospectrum per line, which the
    automatic band reads where there is no coherence). An ``H`` word is
    ignored (``H_real``, ``|H| (dB)``); a quantity word (``accelerance_real``) states the
    quantity. With both real/imag and magnitude/phase, real/imag are used. Separator:
    ``,``, ``;``, tab or white space. Other units a header states are converted, and state
    the quantity: a frequency in kHz; values in m/N, mm/N, um/N, nm/N, m/kN, in/lbf
    (receptance), m/s/N, mm/s/N, in/s/lbf (mobility), m/s^2/N, 1/kg, mm/s^2/N, g/N, g/lbf
    (accelerance; ``(m/s^2)/N``, ``m/(N s^2)`` alike); a coherence in %. Any other
    stated unit (``[V/N]``, ``[rpm]``) is refused, naming the column: a unit read past
    would scale every figure of the fit and the impact.

    *NPZ*: ``freq_hz`` (or ``omega_rad_s``), ``values``, optional ``coherence``,
    ``excitation`` and ``quantity`` (a string), matched as above.

    *MAT*: the analyzer export (``Freq_domain`` in Hz, ``Hf_chan_N``, ``Hf_coh_chan_N``;
    one FRF per N; quantity not stated) or the NPZ names; v7.3 (HDF5) is not supported.

    *UFF*: every dataset 58 of function type 4 (FRF), ASCII or binary; a dataset 58 of
    type 6 (coherence) with the same response/reference DOFs gives its coherence. The
    abscissa must be frequency (specific data type 18, or 0) in Hz or rad/s (units label).
    Quantity from the ordinate specific data types (records 9/10): numerator 8
    displacement -> receptance, 11 velocity -> mobility, 12 acceleration -> accelerance,
    over 13 excitation force, 9 reaction force or 0; numerator 0/1 (unknown/general)
    states nothing; other pairs (e.g. force over acceleration) are refused. Values go to
    SI by the units dataset 164 before the record (none: SI) and the exponents of records
    9/10 (all zero: length over force); axis labels naming other units (``g`` over ``N``
    in an SI file) are warned about. A record whose directions differ in sign (response
    +3, reference -3) is read negated: every FRF is along positive directions.

    Coherence outside [0, 1] is clipped to it with a ``UserWarning`` saying where.
    """
    path, fmt = _resolve(path, format)
    return _read_all(path, fmt, quantity, columns)


def read_frf(path, *, format=None, quantity=None, columns=None, index=None,
             freq_hz=None, conjugate=False, negate=False) -> FRFData:
    """The FRF in a file: the only one, or the one ``index`` picks.

    Parameters
    ----------
    path, format, quantity, columns
        As :func:`read_frfs`; ``format`` may also be ``"complex-lines"``.
    index : int, optional
        Which FRF (``read_frfs(path)[index]``); required when the file holds several
        (see :func:`describe_frfs`).
    freq_hz : array_like of float, optional
        For ``format="complex-lines"`` only (one Python complex literal per line, no
        frequencies in the file): the frequency (Hz) of each line; see
        :func:`read_complex_lines`.
    conjugate : bool, default False
        The file is stored with the other sign convention (Fourier kernel
        ``exp(+i omega t)``): return the complex conjugate of its values.
    negate : bool, default False
        The response was recorded against the force: return the values with their sign
        reversed. :func:`check_sign` tells either case from the data.

    Returns
    -------
    FRFData
    """
    _check_orientation(conjugate, negate)
    return _oriented(_read_one(path, format, quantity, columns, index, freq_hz), conjugate,
                     negate)


def _check_orientation(conjugate, negate) -> None:
    """``TypeError`` unless ``conjugate`` and ``negate`` are booleans."""
    for name, flag in (("conjugate", conjugate), ("negate", negate)):
        if not isinstance(flag, (bool, np.bool_)):
            raise TypeError(f"{name} must be True or False, got {flag!r}")


def _oriented(frf: FRFData, conjugate, negate) -> FRFData:
    """``frf`` read with :func:`read_frf`'s ``conjugate`` (complex conjugate values) and
    ``negate`` (values of reversed sign); itself when neither is asked."""
    if not (conjugate or negate):
        return frf
    values = np.conj(frf.values) if conjugate else frf.values
    return frf._replaced(values=-values if negate else values)


def _read_one(path, format, quantity, columns, index, freq_hz):
    """:func:`read_frf` as the file holds it."""
    index = None if index is None else as_count("index", index)
    path, fmt = _resolve(path, format)
    if fmt == "complex-lines" or freq_hz is not None:
        if fmt != "complex-lines":
            raise ValueError(f"freq_hz= applies to format='complex-lines' only, not to {fmt}")
        if freq_hz is None:       # a bare file states no quantity either: both at once
            also = f", and quantity= one of {one_of(QUANTITIES)}" * (quantity is None)
            raise ValueError(f"{path} holds bare complex values: pass freq_hz= (Hz, one per "
                             f"value line){also}")
        if columns is not None or index not in (None, 0):
            raise ValueError("columns= and index= do not apply to format='complex-lines'")
        return read_complex_lines(path, freq_hz=freq_hz, quantity=quantity)
    frfs = _read_all(path, fmt, quantity, columns)
    if index is None:
        if len(frfs) > 1:
            raise ValueError(f"{path} holds {len(frfs)} FRFs{_listing(path, fmt, columns)}: "
                             f"pass index= (0 to {len(frfs) - 1}) or use read_frfs")
        index = 0
    if index >= len(frfs):
        raise ValueError(f"index must be below {len(frfs)}, the number of FRFs in {path}, "
                         f"got {index}")
    return frfs[index]


def _listing(path, fmt, columns, shown=6) -> str:
    """`` (0: response 1+3, reference 1+3; 1: ...)`` of a UFF file's records, else ``""``."""
    return records_listing([r.meta for r in _read_raw(path, fmt, columns)], shown)


def describe_frfs(path, *, format=None, columns=None):
    """A pandas DataFrame, one row per FRF :func:`read_frfs` returns.

    Columns: ``quantity`` (as the file states it, else None), ``n_lines``, ``fmin_hz``,
    ``fmax_hz``, ``coherence`` (bool), and for UFF ``response_node``, ``response_dir``,
    ``reference_node``, ``reference_dir`` (as stored), ``name`` (ID line 1), ``negated``
    (read negated: directions of opposite sign) and ``to_si`` (the units' factor).

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    format : str, optional, keyword-only
        As in :func:`read_frfs`.
    columns : dict, optional, keyword-only
        As in :func:`read_frfs`.

    Returns
    -------
    pandas.DataFrame
    """
    import pandas as pd

    raws = _read_raw(*_resolve(path, format), columns)
    return pd.DataFrame([{"quantity": r.quantity, "n_lines": r.freq_hz.size,
                          "fmin_hz": r.freq_hz[0], "fmax_hz": r.freq_hz[-1],
                          "coherence": r.coherence is not None, **r.meta} for r in raws])


def write_frf(path, frf, *, format=None, binary=False, response=None, reference=None) -> None:
    """Write one FRF so that :func:`read_frf` reads it back, quantity included.

    Parameters
    ----------
    path : str or os.PathLike
        Overwritten if it exists.
    frf : FRFData
    format : {"csv", "npz", "mat", "uff"}, optional
        Default: from the extension (.csv, .npz, .mat, .uff/.unv).
    binary : bool, default False
        UFF only: binary dataset 58 (float64 frequencies and values, bit-exact round
        trip) instead of ASCII.
    response, reference : (node, direction), optional
        UFF only: the DOFs of record 6, default ``(1, 3)`` (node 1, +Z); directions of
        opposite sign store the FRF negated (it is read back as given).

    Notes
    -----
    CSV: ``# quantity: <q>`` then ``freq_hz,real,imag[,coherence][,excitation]``, shortest
    round-trip decimals (bit-exact). NPZ and MAT (v5): ``freq_hz``, ``values``,
    ``quantity`` [, ``coherence``][, ``excitation``] (bit-exact). How the FRF was
    measured (:attr:`FRFData.window_decay_rate`, :attr:`FRFData.record_length`) is kept
    by CSV (comment lines), NPZ and MAT (scalars) and UFF (ID line 4):
    :mod:`modalid._io_measured`. UFF: dataset 58, function
    type 4, ordinate type 8/11/12 over 13 (force), abscissa type 18 in Hz; coherence as a
    second dataset 58 of type 6 (the excitation's spectrum is not written).
    ASCII UFF holds 12 significant digits per value (format E20.12) and frequencies as
    f0 + k*df with f0, df in 6 digits: a grid not of that form is refused (use binary).
    """
    path = _as_path(path)
    if not isinstance(frf, FRFData):
        raise TypeError(f"frf must be an FRFData, got {type(frf).__name__}")
    fmt = _format_of(path, format, WRITE_FORMATS)
    if not isinstance(binary, bool):
        raise TypeError(f"binary must be True or False, got {binary!r}")
    if fmt != "uff" and (binary or response is not None or reference is not None):
        raise ValueError(f"binary, response and reference apply to UFF files, not to {fmt}")
    arrays = {"freq_hz": frf.freq_hz, "values": frf.values, "quantity": np.str_(frf.quantity)}
    extra = {k: v for k, v in (("coherence", frf.coherence), ("excitation", frf.excitation))
             if v is not None}
    arrays.update(extra)
    if fmt == "csv":
        cols = [frf.freq_hz, frf.values.real, frf.values.imag, *extra.values()]
        head = ",".join(["freq_hz", "real", "imag", *extra])
        rows = (",".join(repr(float(v)) for v in row) for row in zip(*cols))
        with open(path, "w", encoding="utf-8", newline="\n") as fh:
            fh.write(f"# quantity: {frf.quantity}\n{comment_lines(frf)}{head}\n"
                     + "\n".join(rows) + "\n")
        return
    arrays.update({k: np.float64(v) for k, v in statements(frf).items()})
    if fmt == "npz":
        with open(path, "wb") as fh:
            np.savez(fh, **arrays)
    elif fmt == "mat":
        import scipy.io

        with open(path, "wb") as fh:
            scipy.io.savemat(fh, {k: np.asarray(v) for k, v in arrays.items()},
                             oned_as="column")
    else:
        _write_uff(path, frf, binary, _dof("response", response), _dof("reference", reference))
