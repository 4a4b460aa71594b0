"""Model files: the JSON a :class:`modalid.ModalModel` or
:class:`modalid.MultiOutputModalModel` is written to and read from, its units converted to
SI (m/N, rad/s) on reading. Reading never executes anything (``json.loads``).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

__all__ = ["RECEPTANCE_UNITS", "read_model_json"]

_FORMAT = "modalid.ModalModel"

#: receptance units a model JSON may state (``units.receptance``, case-insensitive) and
#: their value in m/N; its ``units.s`` must be rad/s (or 1/s)
RECEPTANCE_UNITS = {"m/n": 1.0, "mm/n": 1e-3, "um/n": 1e-6, "\u00b5m/n": 1e-6,
                    "\u03bcm/n": 1e-6, "nm/n": 1e-9, "m/kn": 1e-3, "mm/kn": 1e-6,
                    "in/lbf": 0.0254 / 4.4482216152605}
_S_UNITS = ("rad/s", "1/s")
#: the fields in receptance units (inverse_mass: receptance times (rad/s)^2 = 1/kg)
_RECEPTANCE_FIELDS = ("residues", "real_residues", "inverse_mass", "flexibility")


def _of(label: str) -> str:
    return f" ({label})" if label else ""


def _json_text(source):
    """``(text, label)``: the JSON text of ``source`` and the file it came from ("" for
    a text)."""

    if isinstance(source, str) and source.lstrip().startswith("{"):
        return source, ""
    if not isinstance(source, (str, os.PathLike)):
        raise TypeError(f"source must be a JSON text or a path, got {type(source).__name__}")
    if isinstance(source, str) and ("\n" in source or not source.strip()):
        raise ValueError(f"not a model JSON text (it does not start with '{{') nor a file "
                         f"name: {source[:60]!r}")
    path = Path(source)
    if not path.is_file():
        raise FileNotFoundError(f"no such file: {str(path)!r}")
    try:
        text = path.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError:
        raise ValueError(f"{path} is not a text file, so not a model JSON file") from None
    if not text.strip():
        raise ValueError(f"{path} is empty: not a model JSON file")
    return text, str(path)


def parse_json(text: str, where: str):
    """``json.loads(text)`` (never executes anything), refused as ``ValueError``
    ("``where``: why") where it is not JSON or nested too deep (RecursionError)."""
    try:
        return json.loads(text)
    except (json.JSONDecodeError, RecursionError) as exc:
        why = f"RecursionError: nested too deep ({exc})" if isinstance(
            exc, RecursionError) else str(exc)
        raise ValueError(f"{where}: {why}") from None


def require_a_field(payload: dict, fields, what: str) -> None:
    """Refuse (``ValueError``: "``what`` holds none ...") a model payload holding none of
    ``fields``: read with every field at its default it was a rigid wall, which
    ``impactpred predict`` hit with exit status 0."""
    if not any(name in payload for name in fields):
        raise ValueError(f"{what} holds none of the model's fields ({', '.join(fields)})")


def _si_payload(payload: dict, label: str) -> dict:
    """``payload`` with its receptance fields in m/N, from the ``units`` it states."""
    units = payload.get("units", {})
    if units is None:
        units = {}
    if not isinstance(units, dict):
        raise ValueError(f"the 'units' field{_of(label)} must be an object such as "
                         f'{{"s": "rad/s", "receptance": "m/N"}}, got {units!r}')
    unknown = sorted(set(units) - {"s", "receptance"})
    if unknown:
        raise ValueError(f"the 'units' field{_of(label)} names {unknown}: a model states "
                         "the units of 's' (rad/s) and 'receptance' only")
    s_unit = units.get("s", "rad/s")
    if str(s_unit).strip().lower() not in _S_UNITS:
        raise ValueError(f"units.s {s_unit!r}{_of(label)} is not supported: poles must be in "
                         "rad/s")
    unit = units.get("receptance", "m/N")
    key = str(unit).replace(" ", "").lower()
    if key not in RECEPTANCE_UNITS:
        raise ValueError(f"units.receptance {unit!r}{_of(label)} is not a known receptance "
                         "unit: use one of m/N, mm/N, um/N, nm/N, m/kN, mm/kN, in/lbf (or "
                         "convert the file to m/N)")
    factor = RECEPTANCE_UNITS[key]
    out = dict(payload, units={"s": "rad/s", "receptance": "m/N"})
    if factor != 1.0:
        for name in _RECEPTANCE_FIELDS:
            if name in payload:
                try:
                    out[name] = (np.asarray(payload[name], dtype=float) * factor).tolist()
                except (TypeError, ValueError) as exc:
                    raise ValueError(f"invalid model JSON{_of(label)}: field {name!r}: "
                                     f"{exc}") from exc
    return out


def read_model_json(source, *, formats=(_FORMAT, "modalid.MultiOutputModalModel")):
    """The fields of a model JSON (text or file), in SI units, and where they came from.

    Parameters
    ----------
    source : str or os.PathLike
        A JSON text (starting with ``{``) or the path of a ``.json`` file.
    formats : tuple of str, keyword-only
        The ``format`` field values accepted.

    Returns
    -------
    payload : dict
        The JSON object, its receptance fields (``residues``, ``real_residues``,
        ``inverse_mass`` in 1/kg, ``flexibility``) converted to m/N from the stated
        ``units.receptance`` (one of :data:`RECEPTANCE_UNITS`; SI when absent).
    label : str
        The file read ("" for a text).

    Raises
    ------
    FileNotFoundError
        No such file.
    ValueError
        An empty file, a text that is not JSON, a ``format`` not in ``formats``, a unit
        not known (``units.s`` must be rad/s); each names the file.
    """
    text, label = _json_text(source)
    kind = " or ".join(f.split(".")[-1] for f in formats)
    payload = parse_json(text, f"{label} is not JSON" if label else f"not a {kind} JSON text")
    stated = payload.get("format") if isinstance(payload, dict) else None
    if stated not in formats:
        where = f"{label} is not a {kind} JSON file" if label else f"not a {kind} JSON text"
        raise ValueError(f"{where}: its 'format' field is missing or wrong ({stated!r}; "
                         f"expected {' or '.join(map(repr, formats))})")
    return _si_payload(payload, label), label
