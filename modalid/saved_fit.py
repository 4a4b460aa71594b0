"""A fit saved with what it decided: :class:`SavedFit`.

A fitted :class:`~modalid.ModalFit` holds its data, its model and its report. A model
saved alone (``ModalModel.to_json``) has lost what a prediction needs to use it well: the
band it describes (above which an impact's force must be carried by a continuation, not
by the fit's pseudo-modes), which of its modes are physical, the verdict and the
driving-point decision. An impact predicted from such a file used the raw model: a fixed
rod identified on 12 modes (7-5999 Hz, 1 % noise) and struck by a mass of its own weight
chattered 23 times with a first "restitution" of -0.85, where its FRF file gives 0.687
and the exact answer is 0.699, with no warning. :class:`SavedFit` keeps the model and the
report together, in one JSON file that ``ModalModel.from_json`` (or
``MultiOutputModalModel.from_json``) still reads as the bare model; ``modalid fit --out``
writes it and ``impactpred predict`` uses it as it uses the FRF file's fit (the same
figures), except for the uncertainty band, which re-identifies the data.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
from sklearn.exceptions import NotFittedError

from ._model_json import _json_text, read_model_json
from ._report import FitReport
from .model import ModalModel
from .multi_output import MultiOutputModalModel

__all__ = ["SavedFit"]

#: the key of a model JSON that holds the fit's report
_KEY = "identification"
#: the verdicts a report may carry
_VERDICTS = ("ok", "suspect", "failed")


def _scalar(value):
    """``value`` as a JSON scalar (bool, int, float, str, None), or raise TypeError."""
    if value is None or isinstance(value, str):
        return value
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value)
    raise TypeError(type(value).__name__)


def _entry(value):
    """A report entry as JSON (a scalar or a list of scalars: a tuple or a 1-D array
    becomes a list), or raise TypeError."""
    if isinstance(value, np.ndarray) and value.ndim == 1:
        value = value.tolist()
    if isinstance(value, (list, tuple)):
        return [_scalar(v) for v in value]
    return _scalar(value)


def _modes_payload(modes: pd.DataFrame) -> dict:
    """The modes table column by column (complex columns as ``[re, im]`` pairs) with each
    column's dtype, so that an empty table comes back with its dtypes too."""
    columns, complex_columns = {}, []
    for name in modes.columns:
        values = modes[name].to_numpy()
        if np.iscomplexobj(values):
            complex_columns.append(str(name))
            columns[str(name)] = [[float(v.real), float(v.imag)] for v in values]
            continue
        try:
            columns[str(name)] = [_scalar(v.item() if hasattr(v, "item") else v)
                                  for v in values]
        except TypeError as exc:
            raise TypeError(f"SavedFit.to_json: the modes table's column {name!r} holds a "
                            f"{exc}, which JSON cannot hold") from None
    return {"columns": columns, "complex_columns": complex_columns,
            "dtypes": {str(name): str(modes[name].dtype) for name in modes.columns}}


def _modes_table(payload, label: str) -> pd.DataFrame:
    """The modes table of :func:`_modes_payload`'s output."""
    if not (isinstance(payload, dict) and isinstance(payload.get("columns"), dict)):
        raise ValueError(f"{label}: its identification's 'modes' must hold 'columns'")
    complex_columns = set(payload.get("complex_columns", []))
    data = {}
    for name, values in payload["columns"].items():
        if name in complex_columns:
            pairs = np.asarray(values, dtype=float).reshape(-1, 2)
            data[name] = pairs[:, 0] + 1j * pairs[:, 1]
        else:
            data[name] = values
    lengths = {len(v) for v in data.values()}
    if len(lengths) > 1:
        raise ValueError(f"{label}: the columns of its identification's 'modes' differ in "
                         f"length ({sorted(lengths)})")
    table = pd.DataFrame(data)
    dtypes = payload.get("dtypes", {})
    try:
        return table.astype({name: dtypes[name] for name in table.columns if name in dtypes})
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{label}: its identification's 'modes' dtypes: {exc}") from None


def _checked_report(entries: dict, label: str, n_outputs: int | None = None) -> dict:
    """``entries`` with the fields a prediction reads checked (ValueError naming
    ``label`` and the field) and ``band_hz`` as a tuple; ``n_outputs``: the rows of a
    multi-output model, whose ``driving_point`` may be a row index."""
    band = entries.get("band_hz")
    try:
        low, top = (float(x) for x in band)  # type: ignore[union-attr]  # None: TypeError
    except (TypeError, ValueError):
        raise ValueError(f"{label}: its identification's band_hz must be two frequencies "
                         f"(Hz), got {band!r}") from None
    if not (math.isfinite(low) and math.isfinite(top) and 0.0 <= low < top):
        raise ValueError(f"{label}: its identification's band_hz must be finite with "
                         f"0 <= low < top, got {band!r}")
    n_modes = entries.get("n_modes")
    if isinstance(n_modes, bool) or not isinstance(n_modes, (int, np.integer)) or n_modes < 0:
        raise ValueError(f"{label}: its identification's n_modes must be an integer >= 0, "
                         f"got {n_modes!r}")
    if entries.get("verdict", "ok") not in _VERDICTS:
        raise ValueError(f"{label}: its identification's verdict must be one of {_VERDICTS}, "
                         f"got {entries.get('verdict')!r}")
    driving = entries.get("driving_point")
    row = (n_outputs is not None and isinstance(driving, (int, np.integer))
           and not isinstance(driving, (bool, np.bool_)) and 0 <= driving < n_outputs)
    if not (row or driving is None or isinstance(driving, (bool, np.bool_))):
        rows = f", or a row index < {n_outputs}" if n_outputs is not None else ""
        raise ValueError(f"{label}: its identification's driving_point must be true, false "
                         f"or null{rows}, got {driving!r}")
    return {**entries, "band_hz": (low, top)}


def _n_outputs(model) -> int | None:
    """The rows of a multi-output model, None for a single FRF's."""
    return len(model.outputs) if isinstance(model, MultiOutputModalModel) else None


@dataclass(frozen=True, eq=False)
class SavedFit:
    """A fit's model and report, without its data: what :meth:`to_json` saves and
    :meth:`from_json` reads back.

    It offers what a prediction reads of a fitted :class:`~modalid.ModalFit`, under the
    same names: ``model_`` and ``report_`` (the band ``report_["band_hz"]`` in Hz, the
    physical modes ``report_["modes"]``, ``n_modes``, ``verdict``, ``verdict_reasons``,
    ``driving_point``, the errors; every report entry that is a number, a string, a
    list of them or the modes table). It holds no data: what needs the data (a re-fit,
    :func:`impactpred.uncertainty.uncertainty_band`) needs the FRF file.

    Through JSON the model comes back exactly (every float round-trips); the report as
    JSON holds it: numbers, strings and booleans exactly, tuples and 1-D arrays as lists
    (``band_hz`` as a tuple), the modes table with its columns' dtypes. Two saved fits
    compare by identity (``==`` is ``is``).

    Attributes
    ----------
    model_ : ModalModel or MultiOutputModalModel
        The identified model, exactly as the fit left it (receptance, m/N; poles in rad/s).
    report_ : FitReport
        The fit's report (see :class:`~modalid.FitReport`), without the entries JSON
        cannot hold.
    source : str or None
        The data the fit was made on (e.g. the FRF file's name), as given.
    record_dofs : tuple of 4 int or None
        The DOFs of the UFF record fitted, ``(response_node, response_dir,
        reference_node, reference_dir)`` as stored (``modalid fit`` keeps them), or None
        (another kind of file, or not given). Where they say a transfer FRF
        (:attr:`dofs_say_transfer`) ``impactpred.predict`` refuses the fit as an impact
        body, as it refuses the record itself, whatever its data look like.
    """

    model_: ModalModel | MultiOutputModalModel
    report_: FitReport
    source: str | None = None
    record_dofs: tuple | None = None

    def __post_init__(self):
        if not isinstance(self.model_, (ModalModel, MultiOutputModalModel)):
            raise TypeError(f"model_ must be a ModalModel or MultiOutputModalModel, got "
                            f"{type(self.model_).__name__}")
        if not isinstance(self.report_, FitReport):
            raise TypeError(f"report_ must be a FitReport, got {type(self.report_).__name__}")
        if self.source is not None and not isinstance(self.source, str):
            raise TypeError(f"source must be a string or None, got {self.source!r}")
        if self.record_dofs is not None:
            dofs = tuple(self.record_dofs)
            if len(dofs) != 4 or not all(isinstance(d, (int, np.integer))
                                         and not isinstance(d, bool) for d in dofs):
                raise ValueError("record_dofs must be None or 4 integers (response node, "
                                 f"its direction, reference node, its direction), got "
                                 f"{self.record_dofs!r}")
            object.__setattr__(self, "record_dofs", tuple(int(d) for d in dofs))
        checked = _checked_report(dict(self.report_), "SavedFit", _n_outputs(self.model_))
        if not isinstance(self.report_["band_hz"], tuple):     # e.g. an array: a tuple
            object.__setattr__(self, "report_", self.report_.replace(band_hz=checked["band_hz"]))

    @property
    def dofs_say_transfer(self) -> bool:
        """Whether :attr:`record_dofs` say the record is a transfer FRF (response and
        force at other nodes or along other axes; False without them)."""
        from ._uff import DOF_KEYS, says_transfer

        if self.record_dofs is None:
            return False
        return says_transfer(dict(zip(DOF_KEYS, self.record_dofs)))

    @classmethod
    def from_fit(cls, fit, *, source=None, record_dofs=None) -> SavedFit:
        """The model and report of a fitted :class:`~modalid.ModalFit` (copied: refitting
        ``fit`` changes nothing here).

        Parameters
        ----------
        fit : ModalFit
            A fitted estimator (FRF or FRF-set fit with a band: ``report_["band_hz"]``).
        source : str or os.PathLike, optional, keyword-only
            What the fit was made on, e.g. the FRF file (kept as a string).
        record_dofs : tuple of 4 int, optional, keyword-only
            The DOFs of the UFF record fitted (see :attr:`record_dofs`).

        Returns
        -------
        SavedFit

        Raises
        ------
        sklearn.exceptions.NotFittedError
            ``fit`` is not fitted.
        ValueError
            Its report has no band (an impulse-response fit).
        """
        if not hasattr(fit, "report_") or not hasattr(fit, "model_"):
            raise NotFittedError("SavedFit.from_fit: the fit is not fitted yet: call "
                                 "fit(data) first")
        if "band_hz" not in fit.report_:
            raise ValueError("SavedFit.from_fit: the fit has no band (report_['band_hz']): "
                             "only a fit of an FRF or an FRF set can be saved with its band")
        text = fit.model_.to_json()
        model = type(fit.model_).from_json(text)               # a copy
        entries = {name: (value.copy() if isinstance(value, pd.DataFrame) else value)
                   for name, value in fit.report_.items()}
        return cls(model_=model, report_=FitReport(entries),
                   source=None if source is None else str(source), record_dofs=record_dofs)

    def to_json(self, path=None) -> str:
        """The model's JSON (as ``model_.to_json()`` writes it) with the report beside it,
        under ``"identification"``; written to ``path`` when given.

        Report entries JSON cannot hold (anything but numbers, strings, booleans, None,
        lists of them and the modes table) are left out. Non-finite numbers are written
        as ``NaN``/``Infinity``, as Python's ``json`` reads them.

        Parameters
        ----------
        path : str or os.PathLike, optional
            A file to write the text to (overwritten).

        Returns
        -------
        str
            The JSON text.
        """
        payload = json.loads(self.model_.to_json())
        report = {}
        for name, value in self.report_.items():
            if name == "modes" and isinstance(value, pd.DataFrame):
                report[name] = _modes_payload(value)
                continue
            try:
                report[name] = _entry(value)
            except TypeError:
                continue                      # not JSON: left out (see the docstring)
        payload[_KEY] = {"source": self.source, "report": report}
        if self.record_dofs is not None:
            payload[_KEY]["record_dofs"] = list(self.record_dofs)
        text = json.dumps(payload, indent=1)
        if path is not None:
            Path(path).write_text(text)
        return text

    @classmethod
    def from_json(cls, source) -> SavedFit:
        """Read a fit written by :meth:`to_json`: a JSON text or the path of a file.

        Parsing JSON never executes anything; the model is validated by its constructor
        and the report's band, mode count, verdict and driving-point decision are
        checked. Errors name the file.

        Parameters
        ----------
        source : str or os.PathLike
            A JSON text, or the path of a file holding one.

        Returns
        -------
        SavedFit

        Raises
        ------
        ValueError
            Not a model JSON, or one without the fit's report (``"identification"``: a
            bare model, e.g. ``ModalModel.to_json``'s; read it with ``from_json`` of its
            class), a malformed report, a model stated in units other than SI (the
            report's receptance figures are SI), or a field out of range.
        """
        text, _ = _json_text(source)
        payload, label = read_model_json(source)
        label = label or "the JSON text"
        block = payload.pop(_KEY, None)
        if block is None:
            raise ValueError(f"{label} holds a bare model, not a saved fit (no "
                             f"'{_KEY}'): read it with "
                             f"{payload['format'].split('.')[-1]}.from_json")
        if not (isinstance(block, dict) and isinstance(block.get("report"), dict)):
            raise ValueError(f"{label}: its '{_KEY}' must be an object holding a 'report' "
                             f"object, got {str(block)[:80]!r}")
        units = json.loads(text).get("units") or {}
        stated = str(units.get("receptance", "m/N")).replace(" ", "").lower()
        if stated != "m/n":
            raise ValueError(f"{label}: a saved fit's report is in SI units, so its model "
                             f"must be too (units.receptance 'm/N', got "
                             f"{units.get('receptance')!r})")
        model_class = (MultiOutputModalModel
                       if payload["format"] == "modalid.MultiOutputModalModel" else ModalModel)
        try:
            model = model_class.from_json(json.dumps(payload))
        except ValueError as exc:
            raise ValueError(f"{label}: {exc}") from None
        entries = dict(block["report"])
        if "modes" in entries:
            entries["modes"] = _modes_table(entries["modes"], label)
        entries = _checked_report(entries, label, _n_outputs(model))
        where = block.get("source")
        dofs = block.get("record_dofs")
        if dofs is not None and not (isinstance(dofs, list) and len(dofs) == 4
                                     and all(type(d) is int for d in dofs)):
            raise ValueError(f"{label}: its identification's record_dofs must be 4 integers "
                             f"or absent, got {str(dofs)[:80]!r}")
        return cls(model_=model, report_=FitReport(entries),
                   source=where if isinstance(where, str) else None,
                   record_dofs=None if dofs is None else tuple(dofs))
