"""UFF units: a file's units datasets 164 and a dataset 58's exponents and axis labels, to SI.

A dataset 164 holds for the datasets after it (none before a record: SI). Its record 2
gives the factors that *divide* a length and a force in the file's units to give them in
m and N (inch-pound: 39.37 and 0.2248). An FRF record's values, a length (displacement,
velocity or acceleration: time is always in s) over a force, go to SI times
``force / length``, or by the exponents its records 9 and 10 state. Private helpers of
:mod:`modalid._uff`; :func:`modalid.io.read_frfs` documents the behaviour.
"""

from __future__ import annotations

import re
import sys
import warnings
from dataclasses import dataclass
from pathlib import Path
from types import FrameType

import numpy as np

from ._io_records import VALUE_UNITS, _normalised_unit

__all__ = ["Units", "SI", "units_datasets", "to_si"]


@dataclass(frozen=True)
class Units:
    """A units dataset 164: its description and its length and force factors (file units
    per m and per N)."""

    description: str
    length: float
    force: float


SI = Units("SI", 1.0, 1.0)
#: the standard units codes of dataset 164 record 1: name, file units per m, per N
STANDARD = {1: ("SI", 1.0, 1.0), 2: ("BG", 3.28083989501312, 0.224808943099710),
            3: ("MG", 1.0, 0.101971621297793), 4: ("BA", 3.28083989501312, 7.23301385120989),
            5: ("MM", 1000.0, 1000.0), 6: ("CM", 100.0, 100.0),
            7: ("IN", 39.3700787401575, 0.224808943099710),
            8: ("GM", 1000.0, 0.101971621297793)}
_DATASET_164 = re.compile(rb"^ {4}-1[ \t]*\r?\n[ \t]*164[ \t]*\r?\n(.*?)^ {4}-1[ \t]*$",
                          re.MULTILINE | re.DOTALL)


def _outside_modalid() -> int:
    """The ``stacklevel`` of the first caller outside ``modalid`` for a warning raised by
    the function that calls this one (whichever reader led there)."""
    package = str(Path(__file__).parent)
    frame: FrameType | None = sys._getframe(1)   # the warner: stacklevel 1
    level = 1
    while frame is not None and frame.f_code.co_filename.startswith(package):
        frame, level = frame.f_back, level + 1
    return level


def units_datasets(path, data: bytes, count: int) -> list:
    """The file's ``count`` units datasets 164 (:class:`Units`), in order, read from its
    text (record 1: code and description; record 2: the factors, ``D`` exponents allowed;
    the temperature's are not needed). A factor that is missing, not a number, zero or
    negative is a ``ValueError`` naming the dataset; factors other than those of a
    standard units code are warned about (they are used)."""
    blocks = _DATASET_164.findall(data)
    if len(blocks) != count:
        raise ValueError(f"{path}: {count} units datasets 164 listed, {len(blocks)} found "
                         "in its text: truncated or corrupt?")
    out = []
    for k, block in enumerate(blocks):
        lines = block.decode("latin-1").splitlines()
        head = lines[0] if lines else ""
        code = int(head[:10]) if head[:10].strip().lstrip("-").isdigit() else None
        description = head[10:30].strip() or f"units code {code}"
        numbers = " ".join(lines[1:]).replace("D", "E").replace("d", "e").split()
        try:
            length, force = (float(v) for v in numbers[:2])
        except ValueError:
            length = force = float("nan")
        if len(numbers) < 2 or not (np.isfinite([length, force]).all() and length > 0
                                    and force > 0):
            raise ValueError(f"{path}: its units dataset 164 number {k + 1} ({description}) "
                             f"does not give a positive length and force factor: "
                             f"{numbers[:2]}")
        standard = STANDARD.get(code) if code is not None else None
        if standard and not np.allclose((length, force), standard[1:], rtol=1e-4):
            warnings.warn(f"{path}: its units dataset 164 ({description}) says code {code} "
                          f"({standard[0]}: factors {standard[1]:.6g}, {standard[2]:.6g}) but "
                          f"gives the factors {length:.6g}, {force:.6g}: read by the "
                          "factors", UserWarning, stacklevel=_outside_modalid())
        out.append(Units(description, length, force))
    return out


def to_si(source, dset, units: Units) -> float:
    """The factor that takes the values of the FRF record ``dset`` (a pyuff dataset 58) to
    SI, in ``units``: ``length^(d_l - n_l) force^(d_f - n_f)`` with the length and force
    exponents of its records 9 (numerator) and 10 (denominator). All zero, as many writers
    leave them: a length over a force; record 9 stating the ratio (length 1, force -1)
    over an empty record 10 is not divided again. Exponents whose ratio is not a length
    over a force are refused in units other than SI (they would scale every figure).
    Axis labels that name another unit than the units give (``g`` over ``N`` in an SI
    file) are warned about; the units win, as the UFF standard says.
    """
    num = [int(dset.get(f"ordinate_{k}_unit_exp", 0) or 0) for k in ("len", "force")]
    den = [int(dset.get(f"orddenom_{k}_unit_exp", 0) or 0) for k in ("len", "force")]
    num = num if any(num) else [1, 0]
    if not any(den):
        den = [0, 0] if num[1] else [0, 1]
    net = (num[0] - den[0], num[1] - den[1])
    if net != (1, -1) and units != SI:
        raise ValueError(f"{source}: its records 9 and 10 state a length^{num[0]} "
                         f"force^{num[1]} over a length^{den[0]} force^{den[1]}, not a length "
                         f"over a force, in the units {units.description}: correct them")
    factor = units.length ** (-net[0]) * units.force ** (-net[1])
    labels = [str(dset.get(k, "") or "").strip() for k in ("ordinate_axis_units_lab",
                                                           "orddenom_axis_units_lab")]
    stated = _label_factor(*labels)
    if stated is not None and not np.isclose(stated, factor, rtol=1e-3):
        warnings.warn(f"{source}: its axis labels say {labels[0]!r} over {labels[1]!r} "
                      f"(x{stated:.6g} to SI), its units ({units.description}) x{factor:.6g}; "
                      "read by its units, as the UFF standard says: if the values are in "
                      "the labels' units, correct its units dataset 164", UserWarning,
                      stacklevel=_outside_modalid())
    return factor


def _label_factor(numerator, denominator):
    """The SI factor the axis labels name (``g`` over ``N``, ``m/s^2/N`` over ``""``), or
    None when they name no unit read here."""
    text = _normalised_unit(numerator)
    if text in ("", "none"):
        return None
    den = _normalised_unit(denominator)
    if den not in ("", "none"):
        text = f"{text}/{den}" if "/" not in text else f"({text})/{den}"
    for units in VALUE_UNITS.values():
        if text in units:
            return units[text]
    return None
