"""How an FRF was measured, in its files: the records' exponential window and length.

:attr:`FRFData.window_decay_rate` (1/s) and :attr:`FRFData.record_length` (s) tell
:class:`modalid.ModalFit` what to model (an exponential window, the record's end); a file
written by :func:`modalid.write_frf` keeps them so that a fit of the file needs no flags:

* CSV: comment lines before the table, ``# window_decay_rate (1/s): 4.6`` and
  ``# record_length (s): 1`` (the unit in parentheses may be left out);
* NPZ and MAT: scalar variables ``window_decay_rate`` and ``record_length``;
* UFF dataset 58 has no field for them: :func:`modalid.write_frf` warns that the file
  loses them.
"""

from __future__ import annotations

import re
import warnings

import numpy as np

#: the statements, with the unit each is written in
MEASUREMENT_UNITS = {"window_decay_rate": "1/s", "record_length": "s"}

_COMMENT = re.compile(r"\s*#\s*(window_decay_rate|record_length)\s*(?:\(\s*(1/s|s)\s*\))?"
                      r"\s*[:=]\s*(\S+)\s*$", re.IGNORECASE)


def stated_in_comment(path, line: str) -> tuple[str, float] | None:
    """``(name, value)`` that a CSV comment line states, None for another line.

    Raises
    ------
    ValueError
        The line names a statement with a wrong unit or a value that is not a number.
    """
    match = _COMMENT.match(line)
    if match is None:
        return None
    name, unit, text = match.group(1).lower(), match.group(2), match.group(3)
    if unit is not None and unit.lower() != MEASUREMENT_UNITS[name]:
        raise ValueError(f"{path} says '{line.strip()}': {name} is in "
                         f"{MEASUREMENT_UNITS[name]}")
    try:
        return name, float(text)
    except ValueError:
        raise ValueError(f"{path} says '{line.strip()}': {name} must be a number") from None


def stated_in_arrays(source, arrays) -> dict:
    """The statements among an NPZ's or MAT file's variables (scalars), by name.

    Raises
    ------
    ValueError
        A statement's variable is not one real number.
    """
    stated = {}
    for name in MEASUREMENT_UNITS:
        if name not in arrays:
            continue
        value = np.asarray(arrays[name])
        if value.size != 1 or value.dtype.kind not in "iuf":
            raise ValueError(f"variable {name!r} of {source} must be one real number "
                             f"({MEASUREMENT_UNITS[name]}), got {value!r}")
        stated[name] = float(value.ravel()[0])
    return stated


def statements(frf) -> dict:
    """What ``frf`` states of how it was measured, by name (those it states)."""
    return {name: getattr(frf, name) for name in MEASUREMENT_UNITS
            if getattr(frf, name) is not None}


def comment_lines(frf) -> str:
    """The CSV comment lines of ``frf``'s statements, each ending in a newline."""
    return "".join(f"# {name} ({MEASUREMENT_UNITS[name]}): {value!r}\n"
                   for name, value in statements(frf).items())


def warn_uff_loses(path, frf) -> None:
    """Warn that the UFF file ``path`` cannot keep ``frf``'s statements (a fit of the
    file must be given them)."""
    kept = statements(frf)
    if kept:
        flags = ", ".join(f"{name}={value:.9g}" for name, value in kept.items())
        warnings.warn(f"{path}: a UFF file has no field for how the FRF was measured "
                      f"({flags}): fit it with those settings (ModalFit), or write a .csv, "
                      ".npz or .mat file, which keeps them", UserWarning, stacklevel=3)
