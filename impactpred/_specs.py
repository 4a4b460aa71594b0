"""What a user gives ``predict`` and ``parse_body``, read: a body as a spec string
(``mass:M``, ``rod:...``, ``spring-mass:...``, ``beam:...``), a saved model or fit (``.json``), a
measured FRF file (identified by a clone of the estimator given) or a model object; a
contact law as a spec string. Errors name the spec or the file.
"""

from __future__ import annotations

import inspect
from pathlib import Path
from typing import Any

from sklearn.base import clone

from data_synth import CantileverBeam, LumpedMass, Rod, SpringMass
from modalid import FRFData, ModalFit, ModalModel, MultiOutputModalModel, SavedFit
from modalid.io import check_sign, read_frf
from modalid._uff import DOF_KEYS, dofs_text, says_transfer
from modalid.io_set import uff_record
from modalid.model import read_model_json
from modalid.receptance import Receptance

from .contact import ContactLaw, Hertz, LinearSpring, Rigid

__all__ = ["READ_OPTIONS", "body_label", "check_estimator", "identify", "parse_contact",
           "read_options_pair"]


_SPECS = {
    "mass": (LumpedMass, ("mass",)),
    "rod": (Rod, ("mass", "transit_time", "support")),
    "spring-mass": (SpringMass, ("mass", "stiffness", "damping_ratio")),
    "beam": (CantileverBeam, ("mass", "time_scale")),
}


def _parse_fields(kind, text, names):
    values, positional = {}, []
    for item in filter(None, (part.strip() for part in text.split(","))):
        if "=" in item:
            key, value = (x.strip() for x in item.split("=", 1))
            if key not in names:
                raise ValueError(f"{kind} spec: unknown field {key!r}; fields are "
                                 f"{', '.join(names)}")
            if key in values:
                raise ValueError(f"{kind} spec: {key} given twice ({key}={values[key]!r} "
                                 f"and {key}={value!r})")
            values[key] = value
        else:
            positional.append(item)
    if len(positional) > len(names):
        raise ValueError(f"{kind} spec: {len(positional)} values {positional} for the "
                         f"{len(names)} fields {names}")
    for name, value in zip(names, positional):
        if name in values:
            raise ValueError(f"{kind} spec: {name} given twice ({value!r} in place and "
                             f"{name}={values[name]!r})")
        values[name] = value
    out = {}
    for key, value in values.items():
        if key == "support":
            out[key] = value
            continue
        try:
            out[key] = float(value)
        except ValueError as exc:
            raise ValueError(f"{kind} spec: {key}={value!r} is not a number") from exc
    return out


#: the :func:`modalid.read_frf` options a body's FRF file may be read with
READ_OPTIONS = ("format", "quantity", "columns", "index", "freq_hz", "conjugate", "negate")


def _read_options(read_options, quantity):
    """``read_frf`` keyword arguments from ``read_options`` (a dict) and ``quantity``."""
    if read_options is None:
        options = {}
    elif isinstance(read_options, dict):
        options = dict(read_options)
    else:
        raise TypeError(f"read_options must be a dict of read_frf options, got "
                        f"{type(read_options).__name__}")
    unknown = sorted(set(options) - set(READ_OPTIONS))
    if unknown:
        raise ValueError(f"read_options: unknown option(s) {unknown}; the options are "
                         f"{list(READ_OPTIONS)}")
    if quantity is not None:
        if options.get("quantity", quantity) != quantity:
            raise ValueError(f"quantity={quantity!r} and read_options['quantity']="
                             f"{options['quantity']!r} disagree: give one")
        options["quantity"] = quantity
    return options


def _saved_model(path: Path):
    """What a saved ``.json`` file holds, in SI units: a :class:`modalid.SavedFit` when it
    carries a fit's report (``modalid fit --out``, ``SavedFit.to_json``), else the bare
    model (a ``ModalModel`` or a ``MultiOutputModalModel``); errors name the file."""
    import json

    payload, label = read_model_json(path)
    if "identification" in payload:               # a fit with its band and verdict
        return SavedFit.from_json(path)
    if payload["format"] == "modalid.MultiOutputModalModel":   # several points: all of them
        try:
            return MultiOutputModalModel.from_json(json.dumps(payload))
        except ValueError as exc:
            raise ValueError(f"{label}: {exc}") from None
    return ModalModel._from_payload(payload, label)


def _checked_frf(path, options, *, label="", check_passive=True):
    """The FRF of ``path``, refused when stored with the other sign convention or, as a
    driving point (``check_passive``), with its sign reversed (see
    :func:`modalid.io.check_sign`)."""
    try:
        data = read_frf(path, **options)
    except (ValueError, TypeError) as exc:     # which body's file, for two of them
        if not label:
            raise
        # a plain error of the same kind: a subclass may need other arguments
        raise (TypeError if isinstance(exc, TypeError) else ValueError)(
            label + str(exc)) from exc
    _check_frf_sign(data, path, label=label, check_passive=check_passive,
                    applied=[k for k in ("conjugate", "negate") if options.get(k)])
    return data


def _check_frf_sign(data, source, *, label, check_passive, in_memory=False,
                    applied=()) -> None:
    """Refuse ``data`` (named ``source``) stored with the other sign convention or, as a
    driving point (``check_passive``), with its sign reversed; the remedy named is a
    reading option (left out where it was ``applied``: it made the problem), or for data
    ``in_memory`` what to do to its values."""
    sign = check_sign(data)
    if sign.verdict == "conjugate" or (sign.verdict == "reversed" and check_passive):
        raise ValueError(label + sign.problem(source, data=in_memory, applied=applied))


def check_estimator(estimator):
    """``estimator``, refused unless it is a :class:`modalid.ModalFit` (or None).

    Parameters
    ----------
    estimator : modalid.ModalFit or None
        The estimator whose settings identify each FRF file (it is cloned, never fitted).

    Returns
    -------
    modalid.ModalFit or None

    Raises
    ------
    TypeError
        Anything else, named (a class instead of an instance, a dict of options).
    """
    if estimator is None or isinstance(estimator, ModalFit):
        return estimator
    if isinstance(estimator, type) and issubclass(estimator, ModalFit):
        raise TypeError(f"estimator must be a ModalFit instance, got the class "
                        f"{estimator.__name__}: give {estimator.__name__}(...)")
    hint = (": a dict of options is ModalFit(**options)" if isinstance(estimator, dict)
            else "")
    raise TypeError(f"estimator must be a modalid.ModalFit (its settings are cloned for "
                    f"each body), got {estimator!r}{hint}")


def is_spec(text) -> bool:
    """Whether ``text`` names an exact model (``mass:M``, ``rod:...``, ...), not a file."""
    kind, sep, _ = str(text).partition(":")
    return bool(sep) and kind in _SPECS and not Path(str(text)).exists()


def identify(spec, *, quantity=None, estimator=None, read_options=None, check_passive=True,
              label=""):
    """``(model, None)`` of a spec, saved model or model object; ``(None, fitted
    ModalFit)`` of an FRF file or an :class:`~modalid.FRFData`, fitted by a clone of
    ``estimator`` (default ``ModalFit()``), or of a fitted ``ModalFit`` (as it is);
    ``(None, SavedFit)`` of a saved fit (a ``.json`` file with the fit's report, or the
    object)."""
    if isinstance(spec, (Receptance, MultiOutputModalModel)):
        return spec, None
    if isinstance(spec, SavedFit):
        return None, _refuse_transfer_fit(spec, label)
    if _in_memory(spec):
        return None, _in_memory_fit(spec, quantity=quantity, estimator=estimator,
                                    read_options=read_options, check_passive=check_passive,
                                    label=label)
    if not isinstance(spec, (str, Path)):
        raise TypeError(f"a body must be a file, a spec string, a model, an FRFData or a "
                        f"fitted ModalFit, got {type(spec).__name__}")
    text = str(spec)
    kind, _, rest = text.partition(":")
    if is_spec(text):
        cls, names = _SPECS[kind]
        try:
            fields = _complete_fields(f"{kind} spec ", text, cls, kind, rest, names)
        except ValueError as exc:                    # named by the body
            raise ValueError(f"{label}{exc}") from exc
        try:
            return cls(**fields), None
        except (TypeError, ValueError) as exc:      # named by the body and its spec
            raise ValueError(f"{label}{kind} spec {text!r}: {exc}") from exc
    path = Path(text)
    if not path.exists():
        raise ValueError(f"body {text!r} is neither an existing file nor a spec "
                         f"({', '.join(k + ':...' for k in _SPECS)}; a rigid wall is a mass "
                         "far heavier than the other body, e.g. mass:1e12)")
    if path.suffix.lower() == ".json":
        saved = _saved_model(path)
        return ((None, _refuse_transfer_fit(saved, f"{label}{path}: "))
                if isinstance(saved, SavedFit) else (saved, None))
    options = _read_options(read_options, quantity)
    data = _checked_frf(path, options, label=label, check_passive=check_passive)
    if getattr(estimator, "passive", "auto") is not True:
        _refuse_transfer_record(path, options, label)
    return None, _fitted(data, estimator, path, label)


def _refuse_transfer_record(path, options, label) -> None:
    """Refuse a UFF record whose DOFs say it is a transfer FRF (response and force at
    other nodes or along other axes): the data of a transfer FRF between points that move
    alike can look passive (a record at node 2 for a force at node 1 predicted a
    restitution of 0.24 with no word). A record along opposite directions of one axis is
    the driving point, read negated (:func:`modalid.read_frfs`); a scalar direction (0)
    at the reference's node does not say which axis, so it is not refused."""
    record = uff_record(path, options)
    if record is None or not says_transfer(record):
        return
    raise ValueError("{}{}: record {} is the response at {} to a force at {}, a transfer FRF "
                     "by its DOFs: a body needs its driving-point FRF (force and response at "
                     "the contact point); give the record measured there (index=N), or, if "
                     "its DOFs are written wrong, fit it as a driving point (passive=True)"
                     .format(label, path, options.get("index") or 0, *dofs_text(record)))


def _refuse_transfer_fit(saved, label):
    """``saved``, unless its UFF record's DOFs say a transfer FRF (as
    :func:`_refuse_transfer_record` refuses the record itself: its data may look
    passive)."""
    if not saved.dofs_say_transfer:
        return saved
    response, force = dofs_text(dict(zip(DOF_KEYS, saved.record_dofs)))
    raise ValueError(f"{label}the saved fit of {saved.source or 'a UFF record'} is of the "
                     f"response at {response} to a force at {force}, a "
                     "transfer FRF by its record's DOFs: a body needs its driving-point FRF "
                     "(force and response at the contact point); fit the record measured "
                     "there, or, if its DOFs are written wrong, fit it again as a driving "
                     "point (passive=True) and save that fit")


def _in_memory_fit(spec, *, quantity, estimator, read_options, check_passive, label):
    """The fit of a body given in memory: a fitted ModalFit as it is, an FRFData fitted by
    a clone of ``estimator``; both checked as a file's data would be (sign, quantity)."""
    name = type(spec).__name__
    if read_options:
        raise ValueError(f"{label}read_options {read_options!r} apply to files, not to the "
                         f"{name} given (give its data as they should be read; a pair of "
                         "read_options, body 1's and body 2's, takes None for it)")
    if isinstance(spec, ModalFit):
        if not hasattr(spec, "model_"):
            raise TypeError(f"{label}the ModalFit is not fitted: fit it first, or give its "
                            "data (a file or an FRFData) and the estimator as estimator=")
        if not hasattr(spec, "data_"):
            raise TypeError(f"{label}the ModalFit was fitted on an impulse response, whose "
                            "band a prediction cannot check: give its model_ as the body")
    data = spec.data_ if isinstance(spec, ModalFit) else spec
    stated = getattr(data, "quantity", None)
    if quantity is not None and stated is not None and quantity != stated:
        raise ValueError(f"{label}quantity={quantity!r}, but the {name} given holds "
                         f"{stated} (for one file's quantity give a pair of read_options, "
                         "e.g. ({'quantity': ...}, None))")
    if isinstance(data, FRFData):
        _check_frf_sign(data, f"the {name}", label=label, check_passive=check_passive,
                        in_memory=True)
    return spec if isinstance(spec, ModalFit) else _fitted(spec, estimator, "the FRFData",
                                                           label)


def _fitted(data, estimator, source, label) -> ModalFit:
    """A clone of ``estimator`` (default ``ModalFit()``) fitted on ``data``; its refusal
    names the body and ``source``."""
    estimator = ModalFit() if estimator is None else clone(estimator)
    try:
        estimator.fit(data)
    except ValueError as exc:
        raise ValueError(f"{label}{source}: {exc}") from None
    return estimator


def parse_contact(spec) -> ContactLaw:
    """``rigid``, ``spring:stiffness=..[,damping=..]``, ``hertz:stiffness=..[,exponent=..]``
    or ``hertz-sphere:radius1=..,youngs_modulus1=..,poisson1=..,youngs_modulus2=..,
    poisson2=..[,radius2=..]``; a ``ContactLaw`` passes through.

    Parameters
    ----------
    spec : str or ContactLaw
        The spec string, SI units (N/m, N/m^1.5, m, Pa).

    Returns
    -------
    ContactLaw
        ``Rigid``, ``LinearSpring`` or ``Hertz``.
    """
    if isinstance(spec, ContactLaw):
        return spec
    if not isinstance(spec, str):
        raise TypeError(f"contact must be a ContactLaw or a spec string, got {spec!r}")
    kind, _, rest = spec.partition(":")
    laws: dict[str, tuple[Any, tuple[str, ...]]] = {
            "spring": (LinearSpring, ("stiffness", "damping")),
            "hertz": (Hertz, ("stiffness", "exponent")),
            "hertz-sphere": (Hertz.from_materials, ("radius1", "youngs_modulus1", "poisson1",
                                                    "youngs_modulus2", "poisson2", "radius2"))}
    if kind == "rigid":
        if rest.strip():
            raise ValueError(f"contact={spec!r}: rigid takes no fields")
        return Rigid()
    if kind not in laws:
        raise ValueError(f"contact={spec!r}: use rigid, spring:..., hertz:... or "
                         "hertz-sphere:...")
    factory, names = laws[kind]
    try:
        return factory(**_complete_fields("contact=", spec, factory, kind, rest, names))
    except (TypeError, ValueError) as exc:          # named by its spec (the CLI's flag)
        if str(exc).startswith(f"contact={spec!r}"):
            raise
        raise type(exc)(f"contact={spec!r}: {exc}") from exc


def _complete_fields(what, text, factory, kind, rest, names) -> dict:
    """The fields of the spec ``text`` (``kind:rest``), refused naming what ``factory``
    requires and the spec lacks (``what``: how the message names the spec, ``"contact="``
    for a contact: the command line says ``--contact`` there)."""
    fields = _parse_fields(kind, rest, names)
    required = [name for name, parameter in inspect.signature(factory).parameters.items()
                if parameter.default is inspect.Parameter.empty and name in names]
    missing = [name for name in required if name not in fields]
    if missing:
        raise ValueError(f"{what}{text!r} lacks {', '.join(missing)} (its fields: "
                         f"{', '.join(names)}, e.g. {kind}:"
                         f"{','.join(f'{n}=...' for n in required)})")
    return fields


def read_options_pair(read_options, specs):
    """Per body, its ``read_options``: a pair as given, or one dict for every body read
    from a file (a body of ``specs`` in memory, an FRFData or a fitted ModalFit, gets
    None)."""
    if isinstance(read_options, (list, tuple)):
        if len(read_options) != 2:
            raise ValueError(f"read_options must be a dict or a pair of them (body 1, body "
                             f"2), got {len(read_options)} items")
        return tuple(read_options)
    return tuple(None if _in_memory(spec) else read_options for spec in specs)


def body_label(spec) -> str:
    """How a body is named in messages: its file or spec, else its type ("an FRFData")."""
    name = type(spec).__name__
    return (str(spec) if isinstance(spec, (str, Path))
            else f"{'an' if name.startswith(('FRF', 'A', 'E', 'I', 'O', 'U')) else 'a'} {name}")


def _in_memory(spec) -> bool:
    """Whether a body is FRF data already read (an FRFData, or a ModalFit's)."""
    return isinstance(spec, (FRFData, ModalFit))
