"""LabVIEW measurement files (``.lvm``, text; ``.lvm.gz`` gzipped): channels of samples.

The format (LabVIEW's "Write To Measurement File", text): a file header ending in
``***End_of_Header***`` (``Separator`` Tab or Comma, ``Decimal_Separator`` point or
comma), then one or more segments, each a header (``Channels``, ``Samples``, ``Delta_X``
per channel, ``Y_Unit_Label``, ...) ending in ``***End_of_Header***``, a line of column
names (``X_Value``, the channels, ``Comment``) and the rows of samples. Several segments
are several acquisitions of the same channels: hits, stacked (hits x samples). A file
with an X column per channel (``X_Columns`` Multi) is refused.

Units are SI on return: a channel whose unit label is ``g`` is multiplied by the standard
gravity 9.80665 m/s^2 (an accelerometer's usual LabVIEW scale), ``kN`` by 1000; other
labels are kept as they are and reported. The time channel is ``X0 + k Delta_X`` of the
first segment (the ``X_Value`` column is empty unless the file was written with it).
Nothing read is executed: numbers are parsed with ``float``.
"""

from __future__ import annotations

import gzip
from pathlib import Path

import numpy as np

__all__ = ["read_lvm", "STANDARD_GRAVITY"]

STANDARD_GRAVITY = 9.80665           # m/s^2 per g
_TO_SI = {"g": STANDARD_GRAVITY, "kn": 1000.0}
_END = "***End_of_Header***"


def _text(path: Path) -> str:
    raw = path.read_bytes()
    if path.suffix.lower() == ".gz":
        try:
            raw = gzip.decompress(raw)
        except (OSError, EOFError) as exc:
            raise ValueError(f"{path} is not a readable gzip file: {exc}") from None
    return raw.decode("utf-8-sig", errors="replace")


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
        Per channel name, ``(label in the file, factor applied)``.

    Raises
    ------
    ValueError
        Naming the file: no header end, an unknown separator, segments of different
        channels or lengths, a value that is not a number.
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
    for block in blocks[2:]:
        # a segment's column names and rows, then (but in the last) the next one's header
        lines = [line for line in block.splitlines() if line.replace(sep, "").strip()]
        if not lines:
            raise ValueError(f"{path}: segment {len(segments) + 1} holds no samples")
        end = 1
        while end < len(lines) and not lines[end].split(sep)[0].strip()[:1].isalpha():
            end += 1
        head = _fields(head_lines, sep)
        names, rows, head_lines = lines[0].split(sep), lines[1:end], lines[end:]
        n = int(head.get("Channels", ["0"])[0])
        cols = [c.strip() for c in names[1:1 + n]]
        try:
            data = np.array([[float(v.replace(",", ".") if comma else v)
                              for v in row.split(sep)[1:1 + n]] for row in rows])
        except ValueError as exc:
            raise ValueError(f"{path}: a sample of segment {len(segments) + 1} is not a "
                             f"number: {exc}") from None
        if data.ndim != 2 or data.shape[1] != n:
            raise ValueError(f"{path}: segment {len(segments) + 1} does not hold {n} "
                             "channels on every row")
        segments.append((cols, data, head))
    cols, first, head = segments[0]
    for k, (c, d, _) in enumerate(segments[1:], start=2):
        if c != cols or d.shape != first.shape:
            raise ValueError(f"{path}: segment {k} holds {c} x {d.shape[0]} samples, segment "
                             f"1 {cols} x {first.shape[0]}: one test per file")

    def number(key, j, default):
        values = head.get(key, [])
        value = values[j] if j < len(values) and values[j] else default
        return float(value.replace(",", ".") if comma else value)

    labels = head.get("Y_Unit_Label", [""] * len(cols))
    channels, units = {}, {}
    for j, name in enumerate(cols):
        label = labels[j] if j < len(labels) else ""
        factor = _TO_SI.get(label.lower(), 1.0)
        stack = np.array([d[:, j] for _, d, _ in segments]) * factor
        channels[name] = stack[0] if len(segments) == 1 else stack
        units[name] = (label, factor)
    step = number("Delta_X", 0, "nan")
    if not step > 0:
        raise ValueError(f"{path}: its Delta_X (sample interval) is {step!r}")
    channels = {"time": number("X0", 0, "0") + step * np.arange(first.shape[0]), **channels}
    return channels, units
