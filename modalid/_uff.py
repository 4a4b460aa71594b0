"""UFF dataset 58 (function at nodal DOF): reading FRFs and their coherence, writing one FRF.

Private helpers of :mod:`modalid.io`, which documents the behaviour (:func:`modalid.io.read_frfs`
for reading, :func:`modalid.io.write_frf` for writing). ``pyuff`` is imported when used.
"""

from __future__ import annotations

import os
import uuid
import warnings

import numpy as np

from ._checks import as_count
from ._io_measured import id_line, stated_in_id_line
from ._io_records import _finite, _Raw
from ._uff_units import SI, to_si, units_datasets

# dataset 58, records 9/10 field 1 (specific data type): numerator codes of our quantities
_UFF_NUMERATOR = {8: "receptance", 11: "mobility", 12: "accelerance"}
_UFF_CODE = {q: c for c, q in _UFF_NUMERATOR.items()}
_UFF_FORCE = (13, 9, 0)  # excitation force, reaction force, or unstated
_UFF_UNITS = {"receptance": "m", "mobility": "m/s", "accelerance": "m/s^2"}


def _uff_delimiters(data):
    """Count the ``    -1`` dataset delimiters the way pyuff finds them."""
    count, ind = 0, -1
    while (ind := data.find(b"    -1", ind + 1)) != -1:
        end = ind + 6
        if end == len(data) or data[end] in (10, 13) or data[end:ind + 80] == b" " * 74:
            count += 1
    return count


def _read_uff(path, columns):
    import pyuff

    data = path.read_bytes()
    delimiters = _uff_delimiters(data)
    if delimiters == 0:
        raise ValueError(f"{path} is not a UFF file: it has no '    -1' dataset delimiters")
    if delimiters % 2:
        raise ValueError(f"{path} is truncated or corrupt: its last dataset has no closing "
                         "'    -1' delimiter")
    try:
        uff = pyuff.UFF(str(path))
        types = [int(t) for t in uff.get_set_types()]
        picks = [i for i, t in enumerate(types) if t == 58]
        sets = uff.read_sets(picks) if picks else []
    except Exception as exc:  # pyuff raises bare Exception for every failure
        raise ValueError(f"cannot read UFF file {path} (truncated or corrupt?): {exc}") from exc
    if not picks:
        raise ValueError(f"{path} holds no dataset 58 (function at nodal DOF), so no FRF; "
                         f"its datasets are of types {types}")
    sets = [sets] if isinstance(sets, dict) else list(sets)
    # a units dataset 164 holds for the datasets after it (none before: SI)
    found = units_datasets(path, data, types.count(164))
    units = [([SI] + found)[types[:i].count(164)] for i in picks]
    records = [(s, u) for s, u in zip(sets, units) if s.get("func_type") == 4]
    if not records:
        raise ValueError(f"{path} has no FRF: its datasets 58 hold function types "
                         f"{sorted({s.get('func_type') for s in sets})}, an FRF is type 4")
    cohs = [s for s in sets if s.get("func_type") == 6]
    return [_uff_raw(path, s, u, number, cohs) for number, (s, u) in enumerate(records)]


#: a record's DOFs as its metadata names them (:func:`dofs_text`, :func:`says_transfer`)
DOF_KEYS = ("response_node", "response_dir", "reference_node", "reference_dir")


def _uff_dofs(dset):
    return tuple(dset.get(k) for k in ("rsp_node", "rsp_dir", "ref_node", "ref_dir"))


def _uff_raw(path, dset, units, number, cohs):
    source = f"{path} (FRF {number}, dataset 58)"
    if dset.get("x") is None or dset.get("data") is None:
        raise ValueError(f"{source} is truncated or corrupt: no data values were read")
    freq = _finite(source, "the abscissa", np.asarray(dset["x"], dtype=float))
    values = _finite(source, "the ordinate", np.asarray(dset["data"]))
    if not np.iscomplexobj(values):
        raise ValueError(f"{source} holds real values (ordinate data type "
                         f"{dset.get('ord_data_type')}), not complex ones (5 or 6): a "
                         "magnitude alone has no phase to fit; export the FRF as complex")
    if not dset.get("num_pts") == values.size == freq.size:
        raise ValueError(f"{source} is truncated or corrupt: its header says "
                         f"{dset.get('num_pts')} values, the file holds {values.size}")
    axis = dset.get("abscissa_spec_data_type", 0)
    if axis not in (0, 18):
        raise ValueError(f"{source} has abscissa specific data type {axis}, not frequency "
                         "(18)")
    unit = str(dset.get("abscissa_axis_units_lab", "")).strip().lower().replace(" ", "")
    if unit in ("rad/s", "rad/sec", "radians/s", "radian/s"):
        freq = freq / (2 * np.pi)
    elif unit not in ("", "none", "hz", "hertz", "1/s"):
        raise ValueError(f"{source} has abscissa units {dset['abscissa_axis_units_lab']!r}; "
                         "Hz or rad/s are accepted")
    num = dset.get("ordinate_spec_data_type", 0)
    den = dset.get("orddenom_spec_data_type", 0)
    if num in (0, 1):            # unknown / general: the file does not say
        stated = None
    elif num in _UFF_NUMERATOR and den in _UFF_FORCE:
        stated = _UFF_NUMERATOR[num]
    else:
        raise ValueError(f"{source} is specific data type {num} over {den}; supported are "
                         "displacement (8), velocity (11) or acceleration (12) over force (13)")
    coh = next((c for c in cohs if _uff_dofs(c) == _uff_dofs(dset)
                and np.size(c["x"]) == freq.size), None)
    coherence = None if coh is None else _finite(source, "the coherence", np.real(coh["data"]))
    dofs = _uff_dofs(dset)
    # an FRF along a negative direction is minus the one along the positive direction:
    # read every record for positive directions (a driving point measured as response +Z,
    # reference -Z, the hammer's direction, is the driving-point FRF negated)
    sign = -1.0 if (dofs[1] or 0) * (dofs[3] or 0) < 0 else 1.0
    factor = to_si(source, dset, units)
    if sign * factor != 1.0:
        values = values * (sign * factor)
    meta = dict(zip(DOF_KEYS,
                    dofs), name=str(dset.get("id1", "")).strip(), negated=sign < 0,
                to_si=factor)
    return _Raw(freq, values, coherence, stated, ("the abscissa", "the ordinate",
                                                  "the coherence dataset"), meta,
                measured=stated_in_id_line(source, dset.get("id4")))


def _write_uff(path, frf, binary, response, reference):
    import pyuff

    f = frf.freq_hz
    spacing = 0                  # binary: abscissa stored per line as float64
    if not binary:               # ASCII: f0 and df stored as E13.5 (6 significant digits)
        f0, df = (float(f"{v:13.5e}") for v in (f[0], f[1] - f[0]))
        if not np.allclose(f0 + np.arange(f.size) * df, f, rtol=0, atol=16 * np.spacing(f[-1])):
            raise ValueError("ASCII UFF dataset 58 stores frequencies as f0 + k*df with f0 and df "
                             "in 6 significant digits, which cannot hold this frequency grid "
                             f"({float(f[0])!r}, {float(f[1])!r}, ... {float(f[-1])!r} Hz): "
                             "pass binary=True (frequencies stored as float64) or use "
                             ".npz/.csv/.mat")
        spacing = 1
    common = dict(binary=int(binary), rsp_node=response[0], rsp_dir=response[1],
                  ref_node=reference[0], ref_dir=reference[1], x=f.copy(),
                  abscissa_spacing=spacing, abscissa_spec_data_type=18,
                  abscissa_axis_units_lab="Hz")
    # the FRF is along positive directions (as read); the record stores it along the
    # directions given: negated where they differ in sign
    sign = -1.0 if response[1] * reference[1] < 0 else 1.0
    dsets = [pyuff.prepare_58(func_type=4, data=sign * frf.values, id1=frf.quantity,
                              id4=id_line(frf) or "NONE",
                              ordinate_spec_data_type=_UFF_CODE[frf.quantity],
                              orddenom_spec_data_type=13,
                              ordinate_axis_units_lab=_UFF_UNITS[frf.quantity],
                              ordinate_len_unit_exp=1, orddenom_force_unit_exp=1,
                              orddenom_axis_units_lab="N", **common)]
    if frf.coherence is not None:
        dsets.append(pyuff.prepare_58(func_type=6, data=frf.coherence.copy(), id1="coherence",
                                      ordinate_spec_data_type=0, orddenom_spec_data_type=0,
                                      **common))
    # pyuff's overwrite mode loses the header of a binary set: append to a fresh file
    tmp = path.with_name(f".{path.name}.{uuid.uuid4().hex}.tmp")
    try:
        with warnings.catch_warnings():  # pyuff leaves the file of a binary set unclosed
            warnings.simplefilter("ignore", ResourceWarning)
            pyuff.UFF(str(tmp)).write_sets(dsets, mode="add")
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def dofs_text(meta) -> tuple:
    """``("1+3", "1-3")``: a UFF record's response and reference DOFs as stored."""
    return (f"{meta['response_node']}{int(meta['response_dir']):+d}",
            f"{meta['reference_node']}{int(meta['reference_dir']):+d}")


def at_reference(meta) -> bool:
    """Whether a UFF record's response is at its reference's node and axis (a driving
    point; along the opposite direction too: such a record is read negated)."""
    return ((meta["response_node"], abs(meta["response_dir"]))
            == (meta["reference_node"], abs(meta["reference_dir"])))


def says_transfer(meta) -> bool:
    """Whether a UFF record's DOFs say it is a transfer FRF: not :func:`at_reference`,
    and not a scalar direction (0) at the reference's node, which names no axis."""
    scalar_here = (meta["response_node"] == meta["reference_node"]
                   and 0 in (meta["response_dir"], meta["reference_dir"]))
    return not (at_reference(meta) or scalar_here)


def records_listing(metas, shown) -> str:
    """`` (0: response 1+3, reference 1+3; 1: ...)`` of UFF records' metadata (the first
    ``shown``), else ``""``."""
    if not all("response_node" in m for m in metas):
        return ""
    items = ["{}: response {}, reference {}".format(i, *dofs_text(m))
             + (" (read negated)" if m.get("negated") else "") for i, m in enumerate(metas)]
    return " (" + "; ".join(items[:shown]) + ("; ..." if len(items) > shown else "") + ")"


def _dof(name, value):
    if value is None:
        return (1, 3)
    try:
        node, direction = value
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a pair (node, direction), got {value!r}") from exc
    node, direction = as_count(f"{name} node", node), as_count(f"{name} direction",
                                                               direction, minimum=-6)
    if direction > 6:
        raise ValueError(f"{name} direction must lie in -6..6, got {direction}")
    return node, direction
