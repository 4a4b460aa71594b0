"""LabVIEW measurement files (``.lvm``, text; ``.lvm.gz`` gzipped): channels of samples.

The format (LabVIEW's "Write To Measurement File", text): a file header ending in
``***End_of_Header***`` (``Separator`` Tab or Comma, ``Decimal_Separator`` point or
comma), then one or more segments, each a header (``Channels``, ``Samples``, ``Delta_X``
per channel, ``Y_Unit_Label``, ...) ending in ``***End_of_Header***``, a line of column
names (``X_Value``, the channels, ``Comment``) and the rows of samples. Several segments
are several acquisitions of the same channels: hits, stacked (hits x samples); with
``Multi_Headings No`` the later ones follow as bare rows, ``Samples`` rows each. A
segment whose rows are not a whole number of its ``Samples``, a row without a finite
number for every channel, anything after the last segment's rows, repeated channel names
or one called ``time``, and an X column per channel (``X_Columns`` Multi) are refused,
naming the file and the row.

Units: a channel labelled ``g`` or ``mg`` is scaled to m/s^2 by the standard gravity
9.80665, ``kN``/``mN``/``lbf``/``kgf`` to N, ``in/s^2``, ``in/s``, ``mm/s``, ``mm/s^2``,
``mm``, ``um``, ``in`` to SI; N, m/s^2, m/s and m are kept; any other label (``V``: an
unscaled sensor) is kept as it is and reported (``units``, factor None), for the caller
to refuse. The time channel is ``k Delta_X`` from 0 (``X0``, an
absolute clock, is not used); a ``Delta_X`` written with fewer than six significant
digits is warned about (its sample rate may be off: give it instead). Nothing read is
executed: numbers are parsed with ``float``; a file not in UTF-8 is read as cp1252.
"""

from __future__ import annotations

import gzip
import re
import warnings
from pathlib import Path

import numpy as np

__all__ = ["read_lvm", "si_factor", "unit_kind", "STANDARD_GRAVITY"]

STANDARD_GRAVITY = 9.80665           # m/s^2 per g
_LBF = 4.4482216152605               # N per lbf


def _table(kind, units):
    return {label: (factor, kind) for label, factor in units.items()}


#: a channel's unit labels (lower case): the factor to SI (N, m/s^2, m/s, m) and the kind
#: of quantity they measure
_UNITS = {**_table("force", {"n": 1.0, "newton": 1.0, "newtons": 1.0, "kn": 1e3, "mn": 1e-3,
                             "lbf": _LBF, "kgf": STANDARD_GRAVITY}),
          **_table("acceleration", {"m/s^2": 1.0, "m/s2": 1.0, "m/s²": 1.0,
                                    "g": STANDARD_GRAVITY, "mg": 1e-3 * STANDARD_GRAVITY,
                                    "mm/s^2": 1e-3, "mm/s2": 1e-3, "in/s^2": 0.0254,
                                    "in/s2": 0.0254}),
          **_table("velocity", {"m/s": 1.0, "mm/s": 1e-3, "in/s": 0.0254}),
          **_table("displacement", {"m": 1.0, "mm": 1e-3, "um": 1e-6, "µm": 1e-6,
                                    "in": 0.0254})}
_END = "***End_of_Header***"


def si_factor(label: str):
    """The factor that takes a channel in unit ``label`` (``g``, ``kN``, ``mm/s``, ...) to
    SI (N, m/s^2, m/s, m): 1.0 for an SI unit or none, None for a unit not known."""
    key = label.lower().replace(" ", "")
    return 1.0 if not key else _UNITS.get(key, (None, None))[0]


def unit_kind(label: str):
    """What a channel in unit ``label`` measures: ``"force"``, ``"acceleration"``,
    ``"velocity"``, ``"displacement"``, or None (no unit, or one not known)."""
    return _UNITS.get(label.lower().replace(" ", ""), (None, None))[1]


def _text(path: Path) -> str:
    raw = path.read_bytes()
    if path.suffix.lower() == ".gz":
        try:
            raw = gzip.decompress(raw)
        except (OSError, EOFError) as exc:
            raise ValueError(f"{path} is not a readable gzip file: {exc}") from None
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:            # a Windows LabVIEW's code page
        return raw.decode("cp1252", errors="replace")


def _fields(lines, sep):
    """The ``key -> values`` of a header's lines (values split on ``sep``)."""
    out = {}
    for line in lines:
        parts = line.split(sep)
        if parts and parts[0].strip():
            out[parts[0].strip()] = [p.strip() for p in parts[1:]]
    return out


def read_lvm(path) -> tuple[dict, dict]:
    """The channels of a LabVIEW measurement file, in SI units.

    Parameters
    ----------
    path : str or Path
        A ``.lvm`` file, or a gzipped one (``.lvm.gz``).

    Returns
    -------
    channels : dict
        ``"time"`` (s, 1-D) and each channel by its name: 1-D for one segment, hits x
        samples for several.
    units : dict
        Per channel name, ``(label in the file, factor applied)``; factor 1.0 for an SI
        label, None for a label not known (kept as it is).

    Raises
    ------
    ValueError
        Naming the file: no header end, an unknown separator, segments of different
        channels or lengths, rows that are not whole samples (see the module docstring).
    """
    path = Path(path)
    text = _text(path)
    blocks = text.split(_END)
    if len(blocks) < 3:
        raise ValueError(f"{path} is not a LabVIEW measurement file: it needs a file header "
                         f"and a segment header, each ending in {_END}")
    # the separator is named before it is known: "Separator<sep>Tab" or "...Comma"
    sep_word = next((line[len("Separator"):].strip(" \t,") for line in blocks[0].splitlines()
                     if line.startswith("Separator")), "Tab")
    seps = {"tab": "\t", "comma": ","}
    if sep_word.lower() not in seps:
        raise ValueError(f"{path}: separator {sep_word!r} is not Tab or Comma")
    sep = seps[sep_word.lower()]
    fhead = _fields(blocks[0].splitlines(), sep)
    comma = fhead.get("Decimal_Separator", ["."])[0] == ","
    if fhead.get("X_Columns", ["No"])[0].lower() == "multi":
        raise ValueError(f"{path} has an X column per channel (X_Columns Multi): write it "
                         "with one X column (No or One), or export the channels as CSV")
    segments: list[tuple[list[str], np.ndarray, dict]] = []
    head_lines = blocks[1].splitlines()
    for b, block in enumerate(blocks[2:], start=2):
        # a segment's column names and rows, then (but in the last) the next one's header
        k = len(segments) + 1
        lines = [line for line in block.splitlines() if line.replace(sep, "").strip()]
        if not lines or not lines[0].strip().lower().startswith("x_value"):
            raise ValueError(f"{path}: segment {k} has no X_Value line of channel names "
                             "after its header")
        end = 1
        while end < len(lines) and not lines[end].split(sep)[0].strip()[:1].isalpha():
            end += 1
        head = _fields(head_lines, sep)
        names, rows, head_lines = lines[0].split(sep), lines[1:end], lines[end:]
        if b == len(blocks) - 1 and head_lines:
            raise ValueError(f"{path}: segment {k} ends at a line that is not samples: "
                             f"{head_lines[0][:60]!r}")
        n = int(head.get("Channels", ["0"])[0])
        cols = [c.strip() for c in names[1:1 + n]]
        data = _samples(path, k, rows, sep, n, comma)
        samples = [int(v) for v in head.get("Samples", []) if v.strip()]
        declared = max(samples) if samples else data.shape[0]
        if declared <= 0 or data.shape[0] % declared:
            raise ValueError(f"{path}: segment {k} holds {data.shape[0]} rows, its header "
                             f"says {declared} samples")
        # Multi_Headings No: later segments follow as bare rows, Samples rows each
        segments += [(cols, part, head) for part in np.split(data, data.shape[0] // declared)]
    cols, first, head = segments[0]
    for k, (c, d, _) in enumerate(segments[1:], start=2):
        if c != cols or d.shape != first.shape:
            raise ValueError(f"{path}: segment {k} holds {c} x {d.shape[0]} samples, segment "
                             f"1 {cols} x {first.shape[0]}: one test per file")
    if len(set(cols)) < len(cols) or "time" in {c.lower() for c in cols}:
        raise ValueError(f"{path}: its channel names {cols} repeat, or one is 'time': "
                         "rename them")
    labels = head.get("Y_Unit_Label", [""] * len(cols))
    channels, units = {}, {}
    for j, name in enumerate(cols):
        label = labels[j] if j < len(labels) else ""
        factor = si_factor(label)
        stack = np.array([d[:, j] for _, d, _ in segments]) * (factor or 1.0)
        channels[name] = stack[0] if len(segments) == 1 else stack
        units[name] = (label, factor)
    text_step = (head.get("Delta_X") or ["nan"])[0]
    step = float(text_step.replace(",", ".") if comma else text_step)
    if not step > 0:
        raise ValueError(f"{path}: its Delta_X (sample interval) is {text_step!r}")
    digits = len(re.sub(r"[^0-9]", "", re.split(r"[eE]", text_step)[0]).lstrip("0"))
    if digits < 6:
        warnings.warn(f"{path}: its Delta_X {text_step!r} has {digits} significant digits: "
                      f"the sample rate {1 / step:.9g} Hz may be off by up to "
                      f"{100 * 0.5 * 10.0 ** (1 - digits):.2g} %; give it with --fs",
                      UserWarning, stacklevel=3)
    # the time from 0 (X0, an absolute clock, would round the steps at 1e9 s)
    channels = {"time": step * np.arange(first.shape[0]), **channels}
    return channels, units


def _samples(path, k, rows, sep, n, comma):
    """The ``(rows, n)`` samples of segment ``k``: every row ``n`` finite numbers after its
    X field."""
    data = np.empty((len(rows), n))
    for i, row in enumerate(rows):
        values = row.split(sep)[1:1 + n]
        try:
            if len(values) != n or not all(v.strip() for v in values):
                raise ValueError(f"{len(values)} fields, some empty")
            data[i] = [float(v.replace(",", ".") if comma else v) for v in values]
        except ValueError as exc:
            raise ValueError(f"{path}: row {i + 1} of segment {k} does not hold {n} numbers "
                             f"({exc}): {row[:60]!r}") from None
        if not np.all(np.isfinite(data[i])):
            raise ValueError(f"{path}: row {i + 1} of segment {k} holds a value that is not "
                             f"finite: {row[:60]!r}")
    return data
