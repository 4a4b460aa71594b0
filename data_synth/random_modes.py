"""Random sets of well-separated modes: a driving point of many modes at random
frequencies, for benchmarks of identification on dense bands."""

from __future__ import annotations

import numpy as np

from modalid import ModalModel
from modalid.validation import as_count, as_positive_scalar

__all__ = ["random_modal_model"]


def random_modal_model(n_modes, freq_range_hz, damping_ratio, *, seed=None) -> ModalModel:
    """A driving point of ``n_modes`` modes at random frequencies, resolvable one from the
    next.

    Frequencies are drawn uniformly on ``freq_range_hz`` and kept when every two lie
    apart by a factor ``1 + max(0.005, 4 damping_ratio)`` (two half-power bandwidths, and
    at least 0.5 %); each mode's damping ratio is ``damping_ratio`` times ``2**u``, ``u``
    uniform on [-1, 1]; its modal mass uniform on [0.5, 5] kg (positive: a passive
    driving point). The draws come in that order from ``numpy.random.default_rng(seed)``,
    so a seed gives one model (``benchmarks/many_modes.py``'s random set is
    ``random_modal_model(50, (200, 19800), zeta, seed=7)``).

    Parameters
    ----------
    n_modes : int
        The number of modes, >= 1.
    freq_range_hz : tuple of float
        ``(low, high)`` (Hz), ``0 < low < high``.
    damping_ratio : float
        The nominal damping ratio, > 0.
    seed : int, numpy.random.Generator or None, keyword-only
        Seed of ``numpy.random.default_rng``.

    Returns
    -------
    modalid.ModalModel
        The modes sorted by frequency; exact (a rational model, no truncation).

    Raises
    ------
    ValueError
        Bad arguments, or ``n_modes`` too many to place that far apart in
        ``100 n_modes`` draws.
    """
    n = as_count("n_modes", n_modes, minimum=1)
    zeta = as_positive_scalar("damping_ratio", damping_ratio)
    if np.ndim(freq_range_hz) != 1 or np.shape(freq_range_hz) != (2,):
        error = TypeError if np.ndim(freq_range_hz) == 0 else ValueError
        raise error(f"freq_range_hz must be a pair (low, high) in Hz, got {freq_range_hz!r}")
    low, high = (as_positive_scalar(f"freq_range_hz[{k}]", v)
                 for k, v in enumerate(freq_range_hz))
    if not low < high:
        raise ValueError(f"freq_range_hz must be (low, high) with low < high, got "
                         f"{tuple(freq_range_hz)!r}")
    rng = np.random.default_rng(seed)
    ratio = 1.0 + max(0.005, 4.0 * zeta)
    kept: list[float] = []
    for f in rng.uniform(low, high, 100 * n):
        if all(max(f, k) > ratio * min(f, k) for k in kept):
            kept.append(f)
        if len(kept) == n:
            break
    if len(kept) < n:
        raise ValueError(f"could place only {len(kept)} of n_modes={n} modes on "
                         f"{low:g}-{high:g} Hz a factor {ratio:g} apart")
    freq = np.sort(kept)
    return ModalModel.from_modes(2 * np.pi * freq, zeta * 2.0 ** rng.uniform(-1, 1, n),
                                 rng.uniform(0.5, 5.0, n))
