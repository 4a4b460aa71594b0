"""Raw impact-hammer records from files: the input of ``modalid hammer``.

A file holds channels sampled together: a time column (s) or none (the sample rate is
then given), the hammer force and the response. Formats:

* ``.npy``: a 2-D array, channels as rows (shape ``(n_channels, n_samples)``, as pyFRF's
  ``measurements_*.npy``: t, force, acceleration) or as columns (the longer axis is time);
* ``.npz``: named arrays, each a channel (1-D) or several hits of it (2-D, hits x
  samples);
* CSV/text: a column per channel, with a header line (names) or without (positions);
  a name's unit in brackets at its end is scaled to SI (``Time (ms)``, ``Force [kN]``,
  ``Acceleration (g)``);
* ``.lvm`` (or gzipped, ``.lvm.gz``): a LabVIEW measurement file (:mod:`modalid._lvm`),
  its channels by name, a channel in g scaled to m/s^2, the time from its ``Delta_X``.

Channels are picked by name or 0-based position (``time``, ``force``, ``response``);
by default by their names (time/t, force/f/excitation, response/acceleration/velocity/
displacement), else by position: three channels are time, force, response; two are
force, response. Several files are several hits, averaged by :func:`frf_from_hammer`.

What a channel's unit or name says is checked, never read past: a force channel's unit
must be a force's (N, kN, mN, lbf, kgf), the response's an acceleration's, velocity's or
displacement's, which then says what the response is (``HammerRecords.response_type``;
its name too: ``Velocity``, ``disp``, ...; the two must agree), a time channel's s, ms or
us. A unit not known (``V``, ``mV``: an unscaled sensor) is refused unless the channel's
scale to SI is given (``force_scale``, ``response_scale``: the sensor's sensitivity, N or
m/s^2, m/s, m per unit of the file).

Nothing read is executed: ``np.load(allow_pickle=False)``, text parsed as numbers.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["HammerRecords", "read_hammer_records"]

_TIME = {"t", "time", "ts", "times", "timesec"}
_FORCE = {"f", "force", "forcen", "excitation", "exc", "hammer", "input"}
_KINDS = {"acceleration": {"acceleration", "accel", "acc", "a", "accelerationms"},
          "velocity": {"velocity", "vel", "v", "velocityms"},
          "displacement": {"displacement", "disp", "x", "displacementm"}}
_RESPONSE = {"response", "resp", "output"}.union(*_KINDS.values())

#: relative scatter of a time column's steps accepted as uniform sampling
_UNIFORM = 1e-4


@dataclass(frozen=True)
class HammerRecords:
    """Force and response records of one or more hits, as :func:`frf_from_hammer` takes.

    Attributes
    ----------
    force, response : ndarray of float, shape (n_hits, n_samples)
    fs : float
        Sample rate (Hz).
    sources : tuple of str
        Per hit, the name of the file it came from.
    channels : str
        Which channels were read, e.g. ``"time 0, force 1, response 2"`` (names or
        positions), from the first file.
    response_type : {"acceleration", "velocity", "displacement"} or None
        What the response is, as its unit or name says (None: they do not say).
    """

    force: np.ndarray
    response: np.ndarray
    fs: float
    sources: tuple
    channels: str = ""
    response_type: str | None = None


def _normal(name) -> str:
    text = str(name).lower().split("[")[0].split("(")[0]
    return re.sub(r"[^a-z]", "", text)


def _load(path: Path, fs=None):
    """``(channels, names, units)``: a dict name -> array (1-D or hits x samples), whether
    the names are the file's (else positions "0", "1", ...) and what a LabVIEW file's
    units said: ``{name: (label, factor)}`` for the channels scaled to SI or not known
    (factor None). Its time channel gives way to ``fs`` (Hz) when given."""
    suffix = path.suffix.lower()
    if suffix == ".lvm" or path.name.lower().endswith(".lvm.gz"):
        from ._lvm import read_lvm

        channels, units = read_lvm(path)
        if fs is not None:
            channels.pop("time")
        return channels, True, {k: v for k, v in units.items() if v[0]}
    if suffix in (".npy", ".npz"):
        try:
            loaded = np.load(path, allow_pickle=False)
        except ValueError as exc:
            raise ValueError(f"cannot read {path} as {suffix} (pickled/object arrays are "
                             f"refused): {exc}") from None
        except (OSError, EOFError) as exc:
            raise ValueError(f"{path} is not a readable {suffix} file: {exc}") from None
        if isinstance(loaded, np.lib.npyio.NpzFile):
            with loaded:
                return {k: loaded[k] for k in loaded.files}, True, {}
        return _positional(path, loaded), False, {}
    if suffix in (".csv", ".tsv", ".txt"):
        return _load_text(path)
    raise ValueError(f"cannot tell the format of {str(path)!r} from its extension "
                     f"{suffix!r}: accepted are .npy, .npz, .csv, .tsv, .txt, .lvm, .lvm.gz")


def _positional(path, array):
    array = np.asarray(array)
    if array.dtype.kind not in "biuf":
        raise ValueError(f"{path} must hold real numbers, got dtype {array.dtype}")
    if array.ndim != 2:
        raise ValueError(f"{path} must hold a 2-D array (channels x samples or samples x "
                         f"channels), got shape {array.shape}")
    channels = array if array.shape[0] <= array.shape[1] else array.T
    return {str(i): row for i, row in enumerate(channels)}


def _load_text(path):
    """``(channels, names, units)`` of a CSV/TSV/TXT file (see :func:`_load`): a header's
    units (``Acceleration (g)``, ``Time [ms]``) scaled to SI (a CSV in g had been read as
    m/s^2, a time in ms as s: 25.6 Hz for 25.6 kHz)."""
    import pandas as pd

    from ._io_records import _decoded_text

    text, encoding = _decoded_text(path)       # UTF-8, or a Windows export's cp1252
    lines = [line for line in text.splitlines()
             if line.strip() and not line.lstrip().startswith("#")]
    if not lines:
        raise ValueError(f"{path} holds no samples")
    sep = next((s for s in (",", ";", "\t") if s in lines[0]), r"\s+")
    tokens = [t.strip() for t in re.split(sep, lines[0].strip())]
    try:
        [float(t) for t in tokens]
        header = None
    except ValueError:
        header = 0
    try:
        table = pd.read_csv(path, sep=sep, comment="#", header=header, encoding=encoding,
                            skipinitialspace=True, engine="python")
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise ValueError(f"cannot parse {path} as a table: {exc}") from None
    values = table.apply(pd.to_numeric, errors="coerce").to_numpy(dtype=float)
    bad = ~np.isfinite(values)
    if np.any(bad):
        row, col = (int(i) for i in np.argwhere(bad)[0])
        raise ValueError(f"column {table.columns[col]!r} of {path} has a missing or "
                         f"non-numeric value at data row {row + 1}: "
                         f"{table.iloc[row, col]!r}")
    if header is None:
        return {str(i): values[:, i] for i in range(values.shape[1])}, False, {}
    channels, units = {}, {}
    for i, name in enumerate(table.columns):
        name = str(name).strip()
        label, factor = _header_unit(name)
        channels[name] = values[:, i] * (factor or 1.0)
        if label is not None:
            units[name] = (label, factor)
    return channels, True, units


#: time units of a column (the others as LabVIEW's labels: :func:`modalid._lvm.si_factor`)
_TIME_UNITS = {"s": 1.0, "sec": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6}


def _header_unit(name: str):
    """``(label, factor to SI)`` of a column name's trailing ``(unit)`` or ``[unit]``
    (``(None, 1.0)`` without one; factor None for a unit not known: the values are kept,
    and said to be)."""
    from ._io_records import split_unit
    from ._lvm import si_factor

    label = split_unit(name)[1]
    if label is None:
        return None, 1.0
    key = label.replace(" ", "")
    return label, _TIME_UNITS.get(key.lower(), si_factor(key))


def _pick(path, channels, named, role, given, words):
    """The channel name of ``role``: the one given (name or position), else by name."""
    keys = list(channels)
    if given is not None:
        if str(given) in channels:
            return str(given)
        if re.fullmatch(r"\d+", str(given)) and int(given) < len(keys):
            return keys[int(given)]
        raise ValueError(f"{path} has no channel {given!r} (--{role}): it has {keys}")
    if named:
        found = [k for k in keys if _normal(k) in words]
        if len(found) == 1:
            return found[0]
        if len(found) > 1:
            raise ValueError(f"{path} has several {role} channels {found}: pick one with "
                             f"--{role}")
    return None


def _channels_of(path, channels, named, *, time, force, response):
    """``(t or None, force, response)`` arrays of one file."""
    picks = {role: _pick(path, channels, named, role, given, words)
             for role, given, words in (("time", time, _TIME), ("force", force, _FORCE),
                                        ("response", response, _RESPONSE))}
    keys = list(channels)
    if picks["force"] is None or picks["response"] is None:
        if time is None and force is None and response is None and len(keys) in (2, 3):
            roles = ("time", "force", "response")[3 - len(keys):]
            picks = dict(zip(roles, keys), **({} if len(keys) == 3 else {"time": None}))
        else:
            raise ValueError(f"{path}: cannot tell its force and response channels among "
                             f"{keys}: name them with --force and --response (and --time)")
    n = np.size(channels[picks["force"]])
    if n < 8:                  # a header and no rows, or a stub: nothing to transform
        raise ValueError(f"{path}: its channels hold {n} samples; a hammer record needs "
                         "at least 8")
    return (None if picks["time"] is None else np.asarray(channels[picks["time"]], float),
            np.asarray(channels[picks["force"]], float),
            np.asarray(channels[picks["response"]], float), picks)


def _rate(path, t, n_samples, fs=None):
    """The sample rate (Hz) of a uniform time column, to 10 significant digits: a time
    column carries the rounding of its own text (pyFRF's step 3.90625000080e-5 s gave
    25600.0000000002 Hz, lines 1 - 2e-14 Hz apart that an ASCII UFF file could not hold
    and a CSV file wrote as 0.9999999999999796). A column uniform with a step rounded in
    its text is exactly uniform with that step, so it cannot be told from an exact rate
    of more digits (51200/31 Hz): that one is rounded too, by at most 5e-10 of itself,
    10^3 times below a sampling clock's accuracy (a crystal's ~1e-6).

    With ``fs`` (Hz) given the column is checked against it to its own rounding: each
    time within ``d`` of ``t_0 + k / fs``, ``d`` the column's largest distance from its
    own uniform grid (its rounding: 4 decimals at 4096 Hz, steps of 0.0002 and 0.0003 s,
    are not uniform to 1e-4 but are 4096 Hz), at most half a step; ``fs`` is returned.
    """
    t = np.ravel(t)
    if t.size != n_samples:
        raise ValueError(f"{path}: its time channel has {t.size} samples, the records "
                         f"{n_samples}")
    steps = np.diff(t)
    step = (t[-1] - t[0]) / (t.size - 1)
    if not step > 0:
        raise ValueError(f"{path}: its time channel does not increase (from {t[0]:.6g} to "
                         f"{t[-1]:.6g} s)")
    uniform = np.max(np.abs(steps - step)) <= _UNIFORM * step
    if fs is None:
        if not uniform:
            raise ValueError(f"{path}: its time channel is not uniformly increasing (steps "
                             f"{steps.min():.6g} to {steps.max():.6g} s): give the sample "
                             "rate with --fs (the column is then checked against it to "
                             "its own rounding)")
        return float(f"{1.0 / step:.10g}")
    k = np.arange(t.size)
    rounding = 0.0 if uniform else float(np.max(np.abs(t - t[0] - k * step)))
    off = float(np.max(np.abs(t - t[0] - k / fs)))
    if rounding > 0.5 * step or off > max(rounding, 1e-6 * (t[-1] - t[0])) + 1e-12 * step:
        raise ValueError(f"{path}: its time channel gives {1 / step:.9g} Hz (its times "
                         f"{off:.3g} s off a {fs:.9g} Hz grid, its own rounding "
                         f"{rounding:.3g} s), --fs says {fs:.9g} Hz")
    return fs


def _unit_note(unit, scale=None) -> str:
    """What a channel's unit label said (a LabVIEW file's, a CSV header's), or the scale
    given for it: scaled to SI, or nothing (SI, or none)."""
    if scale is not None:
        return f" (x {scale:g} given: {unit[0] if unit else 'its values'} to SI)"
    if unit is None or unit[1] == 1.0:
        return ""
    return f" (x {unit[1]:g}: {unit[0]} to SI)"


_FORCE_UNITS = "N, kN, mN, lbf, kgf"
_RESPONSE_UNITS = "m/s^2, mm/s^2, g, in/s^2; m/s, mm/s, in/s; m, mm, um, in"


def _checked_units(path, picks, units, force_scale, response_scale):
    """The response type the channels' units and names state (None: none), after checking
    each picked channel's unit against its role (module docstring)."""
    from ._lvm import unit_kind

    said = {}
    for role, scale, allowed, known in (
            ("time", None, ("time",), "s, ms, us"),
            ("force", force_scale, ("force",), _FORCE_UNITS),
            ("response", response_scale, tuple(_KINDS), _RESPONSE_UNITS)):
        name = picks.get(role)
        if name is None or name not in units or scale is not None:
            continue
        label, factor = units[name]
        kind = ("time" if label.replace(" ", "").lower() in _TIME_UNITS
                else unit_kind(label))
        if factor is None or kind not in allowed:
            what = ("a unit not known here (a sensor's volts need its sensitivity: "
                    f"--{role}-scale)" if factor is None else f"a unit of {kind}")
            raise ValueError(f"{path}: its {role} channel {name!r} is in {label!r}, {what}; "
                             f"a {role} channel is in {known}")
        said[role] = kind
    named = next((kind for kind, words in _KINDS.items()
                  if picks.get("response") is not None
                  and _normal(picks["response"]) in words), None)
    if named and said.get("response") not in (None, named):
        raise ValueError(f"{path}: its response channel {picks['response']!r} says "
                         f"{named} by its name, {said['response']} by its unit: correct "
                         "the header")
    return said.get("response") or named


def read_hammer_records(paths, *, fs=None, time=None, force=None, response=None,
                        force_scale=None, response_scale=None) -> HammerRecords:
    """Force and response records of one or more files (see the module docstring).

    Parameters
    ----------
    paths : sequence of str or Path
        One or more files; their hits are stacked in order.
    fs : float, optional, keyword-only
        Sample rate (Hz); needed when a file has no time channel, checked against it
        (to 1e-6) when it has one.
    time, force, response : str or int, optional, keyword-only
        The channels' names or 0-based positions (default: by name, else by position).
    force_scale, response_scale : float, optional, keyword-only
        What takes the channel's values to SI (N, or m/s^2, m/s, m per unit of the file:
        the sensor's sensitivity for a channel in volts); its stated unit is then not
        read. Default: the unit the file states (none: SI).

    Returns
    -------
    HammerRecords

    Raises
    ------
    FileNotFoundError
        A file is missing.
    ValueError
        Every other problem, on one line naming the file: a format not known, a pickled
        or non-numeric array, channels not found, records of different lengths or sample
        rates, a non-uniform time channel, no sample rate.
    """
    from ._checks import as_positive_scalar

    paths = [Path(p) for p in paths]
    if not paths:
        raise ValueError("give at least one file of records")
    scales = {role: None if value is None else as_positive_scalar(f"{role}_scale", value)
              for role, value in (("force", force_scale), ("response", response_scale))}
    forces, responses, sources, rate, kinds = [], [], [], None, {}
    for path in paths:
        if not path.is_file():
            raise FileNotFoundError(f"no such file: {str(path)!r}")
        channels, named, units = _load(path, fs)
        t, f, r, picks = _channels_of(path, channels, named, time=time, force=force,
                                      response=response)
        kinds[path] = _checked_units(path, picks, units, scales["force"], scales["response"])
        f, r = (np.atleast_2d(a) if scales[role] is None
                else np.atleast_2d(a) / (units.get(picks[role], ("", None))[1] or 1.0)
                * scales[role] for role, a in (("force", f), ("response", r)))
        if f.shape != r.shape or f.ndim != 2:
            raise ValueError(f"{path}: force and response differ in shape, {f.shape} and "
                             f"{r.shape}")
        for name, channel in (("force", f), ("response", r)):
            bad = ~np.isfinite(channel)
            if np.any(bad):
                row, sample = (int(i) for i in np.argwhere(bad)[0])
                count = int(bad.sum())
                raise ValueError(f"{path}: its {name} channel holds "
                                 f"{float(channel[row, sample])!r} (record {row + 1} of "
                                 f"{channel.shape[0]}, sample {sample + 1} of "
                                 f"{channel.shape[1]}; {count} value{'s' * (count > 1)} not "
                                 "finite)")
        file_rate = None if t is None else _rate(path, t, f.shape[1], fs)
        file_rate = fs if fs is not None else file_rate
        if file_rate is None:
            raise ValueError(f"{path} has no time channel: give the sample rate with --fs")
        if rate is not None and abs(file_rate - rate) > 1e-6 * rate:
            raise ValueError(f"{path} is sampled at {file_rate:.9g} Hz, {paths[0]} at "
                             f"{rate:.9g} Hz: one test per command")
        if forces and f.shape[1] != forces[0].shape[1]:
            raise ValueError(f"{path} holds records of {f.shape[1]} samples, {paths[0]} of "
                             f"{forces[0].shape[1]}: records of one length per command")
        rate = file_rate
        forces.append(f)
        responses.append(r)
        sources += [path.name] * f.shape[0]
        if len(forces) == 1:
            read = ", ".join(f"{role} {picks[role]}"
                             + _unit_note(units.get(picks[role]), scales.get(role))
                             for role in picks if picks[role] is not None)
    stated = set(kinds.values()) - {None}
    if len(stated) > 1:
        raise ValueError("the files' responses are of different kinds: "
                         + ", ".join(f"{p.name} {k}" for p, k in kinds.items() if k))
    return HammerRecords(np.concatenate(forces), np.concatenate(responses), float(rate),
                         tuple(sources), read, stated.pop() if stated else None)
