"""Input validation shared by the three packages.

Every helper raises ``TypeError`` for a value of the wrong kind and ``ValueError`` for a
value of the right kind but outside its domain, and always names the argument and the
offending value, so that a user reading the traceback knows what to fix.
"""

from __future__ import annotations

import numbers

import numpy as np

__all__ = [
    "as_real_scalar",
    "as_positive_scalar",
    "as_nonnegative_scalar",
    "as_real_array",
    "as_complex_array",
    "as_choice",
    "as_count",
]


def _describe(value) -> str:
    text = repr(value)
    return text if len(text) <= 80 else text[:77] + "..."


def as_real_scalar(name: str, value) -> float:
    """Return ``value`` as a finite Python float, or raise naming ``name``.

    Parameters
    ----------
    name : str
        The argument's name, for the message.
    value : float
        The value given.

    Returns
    -------
    float
    """
    if isinstance(value, bool) or not isinstance(value, (numbers.Real, np.floating, np.integer)):
        if isinstance(value, np.ndarray) and value.ndim == 0 and np.isrealobj(value):
            value = value.item()
        else:
            raise TypeError(f"{name} must be a real number, got {_describe(value)} "
                            f"of type {type(value).__name__}")
    out = float(value)
    if not np.isfinite(out):
        raise ValueError(f"{name} must be finite, got {out!r}")
    return out


def as_positive_scalar(name: str, value) -> float:
    """Return ``value`` as a finite float > 0, or raise naming ``name``.

    Parameters
    ----------
    name : str
        The argument's name, for the message.
    value : float
        The value given.

    Returns
    -------
    float
    """
    out = as_real_scalar(name, value)
    if out <= 0.0:
        raise ValueError(f"{name} must be positive, got {out!r}")
    return out


def as_nonnegative_scalar(name: str, value) -> float:
    """Return ``value`` as a finite float >= 0, or raise naming ``name``.

    Parameters
    ----------
    name : str
        The argument's name, for the message.
    value : float
        The value given.

    Returns
    -------
    float
    """
    out = as_real_scalar(name, value)
    if out < 0.0:
        raise ValueError(f"{name} must be non-negative, got {out!r}")
    return out


def _as_array(name: str, value, dtype, ndim: int | None = None) -> np.ndarray:
    if isinstance(value, (str, bytes)) or value is None:
        raise TypeError(f"{name} must be array-like of numbers, got {_describe(value)}")
    try:
        arr = np.asarray(value)
    except Exception as exc:  # ragged lists and the like
        raise TypeError(f"{name} must be array-like of numbers, got {_describe(value)}") from exc
    if arr.dtype == object or not (np.issubdtype(arr.dtype, np.number) or arr.dtype == bool):
        raise TypeError(f"{name} must be array-like of numbers, got dtype {arr.dtype} "
                        f"from {_describe(value)}")
    if dtype is float and np.iscomplexobj(arr):
        raise TypeError(f"{name} must be real, got complex values {_describe(value)}")
    arr = arr.astype(dtype, copy=False)
    if not np.all(np.isfinite(arr)):
        bad = arr[~np.isfinite(arr)].ravel()[0]
        raise ValueError(f"{name} must be finite, got {bad!r} among its values")
    if ndim is not None and arr.ndim != ndim:
        raise ValueError(f"{name} must be {ndim}-D, got shape {arr.shape}")
    return arr


def as_real_array(name: str, value, *, ndim: int | None = None) -> np.ndarray:
    """Return a finite float array (copy-free when possible), or raise naming ``name``.

    Parameters
    ----------
    name : str
        The argument's name, for the message.
    value : array_like
        The value given.
    ndim : int, optional, keyword-only
        The number of dimensions required.

    Returns
    -------
    numpy.ndarray of float
    """
    return _as_array(name, value, float, ndim)


def as_complex_array(name: str, value, *, ndim: int | None = None) -> np.ndarray:
    """Return a finite complex array, or raise naming ``name``.

    Parameters
    ----------
    name : str
        The argument's name, for the message.
    value : array_like
        The value given.
    ndim : int, optional, keyword-only
        The number of dimensions required.

    Returns
    -------
    numpy.ndarray of complex
    """
    return _as_array(name, value, complex, ndim)


def as_choice(name: str, value, choices) -> str:
    """Return ``value`` if it is one of the strings ``choices``, or raise naming ``name``.

    Parameters
    ----------
    name : str
        The argument's name, for the message.
    value : str
        The value given.
    choices : sequence of str
        The allowed values.

    Returns
    -------
    str
    """
    if not isinstance(value, str):
        raise TypeError(f"{name} must be one of {one_of(sorted(choices))}, got "
                        f"{_describe(value)}")
    if value not in choices:
        raise ValueError(f"{name} must be one of {one_of(sorted(choices))}, got {value!r}")
    return value


def one_of(choices) -> str:
    """``choices`` as words for a message: ``'a', 'b' or 'c'`` (no Python list)."""
    words = [repr(c) for c in choices]
    if len(words) < 2:
        return words[0] if words else "(none)"
    return f"{', '.join(words[:-1])} or {words[-1]}"


def as_count(name: str, value, *, minimum: int = 0) -> int:
    """Return ``value`` as an int >= ``minimum``, or raise naming ``name``.

    Parameters
    ----------
    name : str
        The argument's name, for the message.
    value : int
        The value given (a bool is refused).
    minimum : int, keyword-only
        The smallest allowed.

    Returns
    -------
    int
    """
    if isinstance(value, bool) or not isinstance(value, (numbers.Integral, np.integer)):
        raise TypeError(f"{name} must be an integer, got {_describe(value)}")
    out = int(value)
    if out < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {out}")
    return out


def as_line_selection(name: str, index, n_lines: int):
    """``index`` as a selection of ``n_lines`` frequency lines, or raise naming ``name``.

    A slice is returned as given; otherwise a 1-D boolean mask of ``n_lines`` or a 1-D
    array of integer indices in range (a single integer is refused: a selection keeps an
    FRF of lines, one line is ``[k]``).

    Returns
    -------
    slice or ndarray of bool or ndarray of int
    """
    if isinstance(index, slice):
        return index
    if isinstance(index, (numbers.Integral, np.integer)) and not isinstance(index, bool):
        raise TypeError(f"{name} must be a slice, a boolean mask or an array of line "
                        f"indices, got the integer {index!r}: for one line pass [{index!r}]")
    out = np.asarray(index)
    if out.ndim != 1 or not (out.dtype == bool or np.issubdtype(out.dtype, np.integer)
                             or out.size == 0):
        raise TypeError(f"{name} must be a slice, a boolean mask or an array of line "
                        f"indices, got {_describe(index)}")
    if out.dtype == bool:
        if out.size != n_lines:
            raise ValueError(f"{name} as a mask must hold {n_lines} values (one per line), "
                             f"got {out.size}")
        return out
    out = out.astype(int)
    if out.size and (out.min() < -n_lines or out.max() >= n_lines):
        raise ValueError(f"{name} holds line indices out of range for {n_lines} lines "
                         f"(from {out.min()} to {out.max()})")
    return out
