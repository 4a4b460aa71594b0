"""Raw FRF records, the common ground of the file readers of :mod:`modalid.io`.

One job: from the columns or arrays a file holds to an :class:`FRFData`. Column headers
and variable names are matched to roles (frequency, real/imag, magnitude/phase, values,
coherence, excitation, quantity); what was read is checked (numeric, finite, vectors); the quantity
the file states is settled against ``quantity=``; a raw record becomes an :class:`FRFData`.

Private helpers of :mod:`modalid.io` (CSV, NPZ and MAT readers), :mod:`modalid._uff` and
:mod:`modalid.io_set`; :func:`modalid.io.read_frfs` documents the names accepted.
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from ._checks import as_choice, one_of
from .frf import FRFData
from .quantities import QUANTITIES

_QUANTITY_WORDS = {"receptance": "receptance", "compliance": "receptance",
                   "mobility": "mobility", "accelerance": "accelerance",
                   "inertance": "accelerance"}


# ------------------------------------------------------------------ column names
_UNITS = {"hz": "hz", "hertz": "hz", "deg": "deg", "degree": "deg", "degrees": "deg",
          "rad": "rad", "radian": "rad", "radians": "rad", "db": "db"}
_WORDS = {
    "freq": {"f", "freq", "frequency", "frequencies"},
    "omega": {"omega", "w", "angular_frequency", "angular_freq"},
    "real": {"re", "real", "real_part"},
    "imag": {"im", "imag", "imaginary", "imag_part", "imaginary_part"},
    "magnitude": {"mag", "magnitude", "abs", "amplitude", "amp", "modulus"},
    "phase": {"phase", "arg", "angle", "phi"},
    "coherence": {"coh", "coherence", "gamma2", "gamma_2"},
    "excitation": {"excitation", "force_spectrum", "input_spectrum", "excitation_spectrum"},
    "values": {"values", "value", "h", "frf", ""},
    "quantity": {"quantity"},
}
_ROLES = {("freq", None): "freq_hz", ("freq", "hz"): "freq_hz", ("", "hz"): "freq_hz",
          ("freq", "rad_s"): "omega_rad_s", ("omega", None): "omega_rad_s",
          ("omega", "rad_s"): "omega_rad_s", ("", "rad_s"): "omega_rad_s",
          ("real", None): "real", ("imag", None): "imag", ("values", None): "values",
          ("magnitude", None): "magnitude", ("magnitude", "db"): "magnitude_db",
          ("", "db"): "magnitude_db", ("phase", "deg"): "phase_deg",
          ("phase", "rad"): "phase_rad", ("phase", None): "phase",
          ("coherence", None): "coherence", ("excitation", None): "excitation",
          ("quantity", None): "quantity"}
TABLE_ROLES = ("freq_hz", "omega_rad_s", "real", "imag", "magnitude", "magnitude_db",
               "phase_deg", "phase_rad", "coherence", "excitation")
ARRAY_ROLES = ("freq_hz", "omega_rad_s", "values", "coherence", "excitation", "quantity")


def _column_role(name):
    """``(role, quantity)`` of a column header or variable name; role None if unknown.

    The name is lower-cased; a trailing ``[unit]``/``(unit)`` counts when it is Hz,
    rad/s, deg, rad or dB; other characters separate words. Words naming a quantity
    (``accelerance_real``) give the quantity, and an ``h`` word (``H_real``) is ignored.
    """
    text, stated = split_unit(str(name).lower().replace("°", "deg"))
    unit = None if stated is None else _role_unit(stated)
    if unit is not None:
        text = f"{text}_{unit}"
    tokens = [t for t in re.sub(r"[^a-z0-9]+", "_", text).split("_") if t]
    quantities = {_QUANTITY_WORDS[t] for t in tokens if t in _QUANTITY_WORDS}
    tokens = [t for t in tokens if t not in _QUANTITY_WORDS]
    unit = None
    if tokens[-2:] == ["rad", "s"]:
        unit, tokens = "rad_s", tokens[:-2]
    elif tokens and tokens[-1] in _UNITS:
        unit, tokens = _UNITS[tokens[-1]], tokens[:-1]
    if len(tokens) > 1 or (tokens == ["h"] and unit is not None):
        tokens = [t for t in tokens if t != "h"]
    word = "_".join(tokens)
    kind = next((k for k, words in _WORDS.items() if word in words), None)
    if kind == "values" and word == "" and unit is not None:
        kind = ""
    role = _ROLES.get((kind, unit))
    if role == "values" and word == "" and not quantities:
        role = None
    return role, (quantities.pop() if len(quantities) == 1 else None)


def _role_unit(stated):
    """The unit a column's role reads itself (Hz, rad/s, deg, rad, dB) from a header's
    bracketed text, as a word (``"rad_s"``), or None."""
    word = re.sub(r"[^a-z0-9]+", "_", str(stated).lower().replace("°", "deg")).strip("_")
    return word if word in _UNITS or word == "rad_s" else None


def _assign_roles(names, allowed, columns, source):
    """Map each role in ``allowed`` to one of ``names`` (``columns`` overrides)."""
    if columns is not None and not isinstance(columns, Mapping):
        raise TypeError(f"columns must be a dict role -> name, got {columns!r}")
    found, lower = {}, {str(n).strip().lower(): n for n in names}
    columns = {} if columns is None else dict(columns)
    for role, name in columns.items():
        as_choice("columns key", role, allowed)
        if str(name).strip().lower() not in lower:
            raise ValueError(f"columns[{role!r}] = {name!r} is not in {source}; it has "
                             f"{list(names)}")
        found[role] = (lower[str(name).strip().lower()], None)
    claimed = {n for n, _ in found.values()}
    for name in names:
        role, quantity = _column_role(name)
        if role is None or role not in allowed or name in claimed or role in columns:
            continue
        if role in found:
            raise ValueError(f"{source} has two {role} columns, {found[role][0]!r} and "
                             f"{name!r}: pass columns={{{role!r}: ...}} to pick one")
        found[role] = (name, quantity)
    return found


# ------------------------------------------------------------------ header units
_G = 9.80665                 # m/s^2 per g (standard gravity)
_LBF = 4.4482216152605       # N per lbf
#: a table's value units (normalised: lower case; spaces, ``^``, ``*``, ``_`` and ``\u00b7``
#: dropped, ``\u00b2`` as 2): the quantity each states and its value in SI
VALUE_UNITS = {
    "receptance": {"m/n": 1.0, "mm/n": 1e-3, "um/n": 1e-6, "\u00b5m/n": 1e-6,
                   "\u03bcm/n": 1e-6, "nm/n": 1e-9,
                   "m/kn": 1e-3, "mm/kn": 1e-6, "in/lbf": 0.0254 / _LBF},
    "mobility": {"m/s/n": 1.0, "(m/s)/n": 1.0, "m/(ns)": 1.0, "m/(sn)": 1.0,
                 "mm/s/n": 1e-3, "(mm/s)/n": 1e-3, "in/s/lbf": 0.0254 / _LBF,
                 "(in/s)/lbf": 0.0254 / _LBF},
    "accelerance": {"m/s2/n": 1.0, "(m/s2)/n": 1.0, "m/(ns2)": 1.0, "m/(s2n)": 1.0,
                    "1/kg": 1.0, "kg-1": 1.0, "g/n": _G, "(g)/n": _G, "g/lbf": _G / _LBF,
                    "mm/s2/n": 1e-3, "(mm/s2)/n": 1e-3},
}
#: frequency units a table's frequency column may state, and their value in Hz
FREQUENCY_UNITS = {"khz": 1e3, "kilohertz": 1e3}
#: bracketed words that are units, though without a ``/`` (refused unless known above)
_BARE_UNITS = {"mhz", "ghz", "rpm", "cpm", "s", "ms", "v", "mv", "n", "m", "mm", "um", "g",
               "kg", "pa", "db", "%"}


def split_unit(name):
    """``(text, unit)``: a column header without its trailing ``[unit]`` or ``(unit)``
    (brackets may nest: ``real [(m/s)/N]``), and that unit (None when there is none)."""
    text = str(name).strip()
    if not text or text[-1] not in ")]":
        return text, None
    depth = 0
    for i in range(len(text) - 1, -1, -1):
        depth += text[i] in ")]"
        depth -= text[i] in "[("
        if depth == 0:
            return (text[:i].strip(), text[i + 1:-1].strip()) if i > 0 else (text, None)
    return text, None


def _normalised_unit(text):
    text = str(text).strip().lower().replace("\u00b2", "2")
    return re.sub(r"[\s^*_\u00b7]+", "", text)


def header_unit(name):
    """The unit a column header states in a trailing ``[unit]`` or ``(unit)``, normalised,
    or None: none stated, one :func:`_column_role` reads itself (Hz, rad/s, deg, rad,
    dB), or a bracket that names no unit (``Re(H)``, ``real [-]``, ``coherence
    (gamma^2)``: a unit has a ``/`` or is one of a few bare unit words, such as kHz, rpm,
    g, V)."""
    _, stated = split_unit(name)
    if stated is None:
        return None
    unit = _normalised_unit(stated)
    if not unit or _role_unit(unit) is not None:
        return None
    known = unit in FREQUENCY_UNITS or any(unit in units for units in VALUE_UNITS.values())
    return unit if (known or "/" in unit or unit in _BARE_UNITS) else None


def same_unit(source, *names) -> None:
    """Refuse value columns (a real and an imaginary part) whose units differ in scale: a
    unit stated on one scales that column only (``real [mm/N]`` with ``imag`` read the
    real part in m/N, the imaginary part 1000 times too large)."""
    units = [header_unit(name) for name in names]
    factors = {1.0 if unit is None else unit_factor(source, name, "real", unit)[0]
               for name, unit in zip(names, units)}
    if len(factors) > 1:
        said = ", ".join(f"{name!r}: {unit or 'none'}" for name, unit in zip(names, units))
        raise ValueError(f"the columns of {source} state different units ({said}): state "
                         "the same unit on each")


def quantity_in_comment(source, line) -> set:
    """The quantity a table's comment line states (``# quantity: accelerance``), as a set
    of none or one; a ``# unit: ...`` comment is refused (it is not read: the columns'
    headers state units, ``real [mm/N]``)."""
    m = re.match(r"\s*#\s*(quantity|units?)\s*[:=]\s*(\S*)", line, re.IGNORECASE)
    if not m:
        return set()
    if m.group(1).lower() != "quantity":
        raise ValueError(f"{source} says '{line.strip()}': a unit comment is not read; state "
                         "the unit in the value columns' headers (real [mm/N], imag [mm/N])")
    word = re.sub(r"[^A-Za-z].*", "", m.group(2)).lower()
    if word not in _QUANTITY_WORDS:
        raise ValueError(f"{source} says '# quantity: {m.group(2)}'; the quantity must be "
                         f"one of {one_of(QUANTITIES)}")
    return {_QUANTITY_WORDS[word]}


def unit_factor(source, name, role, unit):
    """``(factor, quantity)``: what a column's stated ``unit`` multiplies its values by to
    reach SI (Hz for a frequency), and the quantity it states (None for a frequency).

    A frequency column may state kHz (Hz and rad/s are read with its role); a real,
    imaginary or magnitude column the units of :data:`VALUE_UNITS` (m/N, mm/N, m/s/N,
    m/s^2/N, g/N, in/lbf, ...; a magnitude in dB: of the linear magnitude, the caller
    adds ``20 log10(factor)``); a coherence %. Any other unit is a ``ValueError`` naming
    the column: a unit read past silently would scale every figure. A phase column's unit
    is read with its role, an excitation column's is not read (its scale does not matter).
    """
    if role in ("freq_hz", "omega_rad_s"):
        if role == "freq_hz" and unit in FREQUENCY_UNITS:
            return FREQUENCY_UNITS[unit], None
        raise ValueError(f"column {name!r} of {source} states the unit {unit!r}: a frequency "
                         "must be in Hz, kHz or rad/s (say so in the header, e.g. freq [Hz])")
    if role == "coherence":
        if unit in ("-", "1", ""):
            return 1.0, None
        if unit == "%":
            return 0.01, None
        raise ValueError(f"column {name!r} of {source} states the unit {unit!r}: a coherence "
                         "is a ratio (no unit, or %)")
    if role in ("real", "imag", "magnitude", "magnitude_db"):
        for quantity, units in VALUE_UNITS.items():
            if unit in units:
                return units[unit], quantity
        raise ValueError(f"column {name!r} of {source} states the unit {unit!r}, which is not "
                         "a receptance, mobility or accelerance unit read here: use one of "
                         "m/N, mm/N, um/N, in/lbf; m/s/N, mm/s/N; m/s^2/N, 1/kg, g/N, g/lbf "
                         "(or drop the unit from the header and give the values in SI)")
    return 1.0, None


_HELP = ("accepted names (case-insensitive, any word separator, optional [unit]): "
         "frequency f/freq/frequency [Hz] or omega/w [rad/s] (e.g. freq_hz, omega_rad_s); ")
TABLE_HELP = _HELP + ("real re/real + imag im/imag, or magnitude mag/abs (dB if the name "
                      "says so, e.g. mag_db) + phase_deg or phase_rad; coherence coh/coherence;"
                      " excitation excitation/force_spectrum")
ARRAY_HELP = _HELP + ("values values/H/frf (complex); coherence coh/coherence; excitation "
                      "excitation/force_spectrum; quantity")


# ------------------------------------------------------------------ raw records
@dataclass
class _Raw:
    """One FRF as read, before the quantity is settled."""

    freq_hz: np.ndarray
    values: np.ndarray
    coherence: np.ndarray | None
    quantity: str | None
    names: tuple = ("freq_hz", "values", "coherence")
    meta: dict = field(default_factory=dict)
    excitation: np.ndarray | None = None
    #: how it was measured (``window_decay_rate``, ``record_length``), as the file states
    measured: dict = field(default_factory=dict)


def _finite(source, name, arr):
    arr = np.asarray(arr)
    if arr.dtype.kind not in "biufc":
        raise ValueError(f"{name} of {source} must be numeric, got dtype {arr.dtype}")
    bad = ~np.isfinite(arr)
    if np.any(bad):
        i = int(np.argmax(bad))
        raise ValueError(f"{name} of {source} holds {arr.ravel()[i].item()!r} at index {i} "
                         "(missing or not finite)")
    return arr


def _vector(source, name, arr):
    arr = np.asarray(arr)
    if arr.ndim == 2 and 1 in arr.shape:
        arr = arr.ravel()
    if arr.ndim != 1:
        raise ValueError(f"{name} of {source} must be a vector, got shape {arr.shape}")
    return _finite(source, name, arr)


def _settle_quantity(source, stated, quantity):
    if quantity is not None:
        as_choice("quantity", quantity, QUANTITIES)
    if stated is not None and quantity is not None and stated != quantity:
        raise ValueError(f"{source} says its FRF is {stated} but quantity={quantity!r} was "
                         "passed: drop the argument, or, if the file says it wrong, correct "
                         "what it states (a '# quantity:' line, a column's unit or quantity "
                         "word, a UFF's data types, an npz/mat 'quantity')")
    if stated is None and quantity is None:
        raise ValueError(f"{source} does not say which quantity its FRF is: pass "
                         f"quantity= one of {one_of(QUANTITIES)}")
    return stated or quantity


def _build(source, raw, quantity):
    """FRFData from a raw record; coherence outside [0, 1] is clipped with a warning."""
    quantity = _settle_quantity(source, raw.quantity, quantity)
    f_name, v_name, c_name = raw.names
    if raw.freq_hz.size != raw.values.size:
        raise ValueError(f"{f_name} and {v_name} of {source} differ in length: "
                         f"{raw.freq_hz.size} and {raw.values.size}")
    for name, arr in ((f_name, raw.freq_hz), (c_name, raw.coherence)):
        if arr is not None and np.iscomplexobj(arr) and np.any(np.imag(arr) != 0):
            raise ValueError(f"{name} of {source} must be real, got complex values")
    if not np.iscomplexobj(raw.values):
        raise ValueError(f"{v_name} of {source} is real, not complex: a measured FRF has a "
                         "phase (a magnitude alone cannot be fitted); store it as complex, "
                         "even where its imaginary part is zero (MATLAB: complex(x, 0))")
    freq = np.real(raw.freq_hz).astype(float)
    coherence = raw.coherence
    if coherence is not None:
        coherence = np.real(coherence).astype(float)
        if coherence.size != raw.freq_hz.size:
            raise ValueError(f"{c_name} of {source} has {coherence.size} lines, "
                             f"{f_name} has {raw.freq_hz.size}")
        out = (coherence < 0) | (coherence > 1)
        if np.mean(coherence > 1.5) > 0.5:     # not rounding: a percentage
            raise ValueError(f"{c_name} of {source} exceeds 1 at {np.count_nonzero(out)} of "
                             f"{coherence.size} lines (median {np.median(coherence):.4g}): "
                             "a coherence in %? say so in its header (coherence [%])")
        if np.any(out):
            i = int(np.argmax(np.abs(coherence - np.clip(coherence, 0, 1))))
            warnings.warn(f"{c_name} of {source} lies outside [0, 1] at {np.count_nonzero(out)} "
                          f"lines (worst {coherence[i]:.6g} at {freq[i]:.6g} Hz); "
                          "clipped to [0, 1]", UserWarning, stacklevel=4)
            coherence = np.clip(coherence, 0.0, 1.0)
    excitation = raw.excitation
    if excitation is not None:
        if np.iscomplexobj(excitation) and np.any(np.imag(excitation) != 0):
            raise ValueError(f"the excitation of {source} must be real (an autospectrum), "
                             f"got complex values")
        excitation = np.real(excitation).astype(float)
    try:
        return FRFData(freq, raw.values.astype(complex), quantity=quantity,
                       coherence=coherence, excitation=excitation, **raw.measured)
    except ValueError as exc:
        raise ValueError(f"{source}: {exc}") from exc


def _decoded_text(path) -> tuple[str, str]:
    """``(text, encoding)`` of a text file: ``"utf-8-sig"``, or ``"cp1252"`` for one that
    is not UTF-8 (an analyzer's Windows export: ``µm/N`` in a header is the byte 0xB5);
    a UTF-16 file, or one with NUL bytes in its first 512 bytes, is refused naming it."""
    with open(path, "rb") as fh:
        raw = fh.read()
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise ValueError(f"{path} is UTF-16 text (an Excel 'Unicode text' export): save it "
                         "as UTF-8 (CSV UTF-8)")
    if b"\0" in raw[:512]:
        raise ValueError(f"{path} is a binary file, not a text table (NUL bytes in its "
                         "first 512 bytes)")
    for encoding in ("utf-8-sig", "cp1252"):
        try:
            return raw.decode(encoding), encoding
        except UnicodeDecodeError as exc:
            why = exc
    raise ValueError(f"{path} is neither UTF-8 nor Windows-1252 text: {why}")


def _text_head(path):
    """The first line of ``path`` when the file starts as text (no NUL byte in its first
    512 bytes, not a MATLAB 5 header), else None."""
    with open(path, "rb") as fh:
        head = fh.read(512)
    if not head or b"\0" in head or head.startswith(b"MATLAB"):
        return None
    try:
        text = head.decode("utf-8")
    except UnicodeDecodeError as exc:
        if exc.start < len(head) - 3:     # not a character cut by the 512 bytes
            return None
        text = head[:exc.start].decode("utf-8")
    return text.strip().splitlines()[0][:60] if text.strip() else ""
