"""How an FRF was measured, in its files: the records' exponential window and length.

:attr:`FRFData.window_decay_rate` (1/s) and :attr:`FRFData.record_length` (s) tell
:class:`modalid.ModalFit` what to model (an exponential window, the record's end); a file
written by :func:`modalid.write_frf` keeps them so that a fit of the file needs no flags:

* CSV: comment lines before the table, ``# window_decay_rate (1/s): 4.6`` and
  ``# record_length (s): 1`` (the unit in parentheses may be left out);
* NPZ and MAT: scalar variables ``window_decay_rate`` and ``record_length``;
* UFF dataset 58: its ID line 4 (80 characters of free text), the statements without
  their units, separated by ``;``: ``window_decay_rate: 4.6; record_length: 1`` (to 12
  significant digits where the shortest exact decimals would not fit).

Read back, a statement is its name, an optional unit in brackets, ``:`` or ``=`` (or
nothing), the value and an optional unit (``# record_length = 2.0 [s]``, ``# record_length:
2 s # remark``). In a CSV a statement in another unit, not a number or out of range is
refused; in a UFF ID line, another program's free text as often as ours, it is left out
with a warning.
"""

from __future__ import annotations

import re
import warnings

import numpy as np

#: the statements, with the unit each is written in
MEASUREMENT_UNITS = {"window_decay_rate": "1/s", "record_length": "s"}

#: a statement begins with its name; the rest must read ``[(unit)] [:|=] value [unit]``
#: (a trailing ``# remark`` allowed)
_NAME = re.compile(r"\s*(window_decay_rate|record_length)\b", re.IGNORECASE)
_REST = re.compile(r"\s*(?:[(\[]\s*([^)\]]*?)\s*[)\]])?\s*[:=]?\s*([^\s#;]+)"
                   r"(?:\s*[(\[]?\s*([^\s#;)\]]+)\s*[)\]]?)?\s*(?:#.*)?$")
#: the words of the messages (a name with underscores would read as a flag on the
#: command line, :func:`modalid._cli.in_flags`)
_WORDS = {"window_decay_rate": "the window's decay rate", "record_length": "the record length"}


def _stated(path, text: str, line: str, form: str) -> tuple[str, float] | None:
    """``(name, value)`` that ``text`` (of the file's ``line``) states, None for text
    that names no statement; ``form`` the format's way of writing it (``"{name}
    ({unit}): VALUE"``), for the message.

    Raises
    ------
    ValueError
        A statement in another unit, of a value that is not a number, or out of range
        (a decay rate finite and >= 0, a record length finite and > 0), naming ``path``
        and quoting ``text``.
    """
    named = _NAME.match(text)
    if named is None:
        return None
    name = named.group(1).lower()
    unit, words = MEASUREMENT_UNITS[name], _WORDS[name]
    rest = _REST.match(text[named.end():])
    said = f"{path} says '{line.strip()}'"
    if rest is None:
        raise ValueError(f"{said}: write it as '{form.format(name=name, unit=unit)}'")
    try:
        value = float(rest.group(2))
    except ValueError:
        raise ValueError(f"{said}: {words} must be a number ({unit})") from None
    for stated in (rest.group(1), rest.group(3)):
        if stated is not None and stated.replace(" ", "").lower() != unit:
            raise ValueError(f"{said}: {words} is stated in {unit}, not {stated!r}")
    if not np.isfinite(value) or value < 0 or (value == 0 and name == "record_length"):
        bound = ">= 0" if name == "window_decay_rate" else "> 0"
        raise ValueError(f"{said}: {words} must be finite and {bound} ({unit})")
    return name, value


def stated_in_comment(path, line: str) -> tuple[str, float] | None:
    """``(name, value)`` that a CSV comment line states, None for another line.

    Raises
    ------
    ValueError
        The line names a statement with a wrong unit or a value that is not a number.
    """
    text = line.lstrip()
    return (_stated(path, text[1:], line, "# {name} ({unit}): VALUE") if text.startswith("#")
            else None)


def stated_in_id_line(path, line) -> dict:
    """The statements of a UFF dataset's ID line (``;``-separated), by name.

    The line is another program's free text as often as ours: a part that names a
    statement but does not read as one is left out with a ``UserWarning`` saying so (a
    fit of the file then models what its settings say).
    """
    stated = {}
    for part in str(line or "").split(";"):
        try:
            said = _stated(f"{path}'s ID line 4", part, part, "{name}: VALUE")
        except ValueError as exc:
            warnings.warn(f"{exc}; left out", UserWarning, stacklevel=6)
            continue
        if said is not None:
            stated[said[0]] = said[1]
    return stated


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


#: the characters of a UFF ID line
ID_LINE_LENGTH = 80


def id_line(frf) -> str:
    """The UFF ID line of ``frf``'s statements (at most :data:`ID_LINE_LENGTH`
    characters), empty when it states none."""
    said = statements(frf).items()
    line = "; ".join(f"{name}: {value!r}" for name, value in said)
    if len(line) > ID_LINE_LENGTH:                   # 12 digits: at most 72 characters
        line = "; ".join(f"{name}: {value:.12g}" for name, value in said)
    return line
