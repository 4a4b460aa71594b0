"""The record end's terms a fit does not model, taken out of the data and fitted again.

A fit with ``record_length`` models how the record's end scales each free decay (its
residue times ``1 - exp(p_w T)``) and, for an acceleration with a mass line, the ``A_2 /
x^2`` the mass line reads; not ``A_1 / x`` (velocity and acceleration) nor, without a
mass line, an acceleration's ``A_2 / x^2`` (:mod:`modalid._window`). Both are sums over
the physical modes of what is left of each at the record's end; where a mode has not
died out within the record they rule the band's lowest lines, and the fit stands a lower
pseudo-mode in for them: a free mass under a grounded body. Given a first fit's modes
they are known, so they are taken out of the data and the fit repeated once (one
repetition moved a fixed rod's restitution from 0.224 to 0.6974, a second by 0).
"""

from __future__ import annotations

import warnings

import numpy as np

from ._fit_one import _say_again
from ._window import a2_unmodelled, record_end_terms
from .frf import FRFData

__all__ = ["refit_without_record_end", "REFIT_ABOVE"]

#: the share of the data at the band's lowest lines (:func:`unmodelled_record_end`) above
#: which the terms are taken out and the fit repeated: a fixed rod's 1 s unwindowed
#: record at 1 % noise had 6 % there and predicted a restitution of 0.548 for 0.690
#: (0.6900 refitted); the benchmark's windowed records have 0.00001-0.044
REFIT_ABOVE = 0.01


def refit_without_record_end(est, data: FRFData, auto: bool):
    """Fit ``data`` with ``est`` (``ModalFit._fit_weighted``) and, where the record end's
    unmodelled terms exceed :data:`REFIT_ABOVE` of the band's lowest lines, fit it again
    with the first fit's terms taken out; returns ``est``.

    The refit's report says what was taken out (``record_end_removed``: the share
    before) and judges what is left (``record_end_unmodelled``: the terms of its own
    modes less those taken out, :func:`modalid._window.unmodelled_record_end`);
    ``data_`` is the data as given, on the refit's band, so that ``score`` and
    ``plot_fit`` (the structure windowed again, the terms included) compare
    with what was measured. The warnings said are the fit's that stands.
    """
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        est._fit_weighted(data, auto)
    share = est.report_.get("record_end_unmodelled")
    if share is None or not share > REFIT_ABOVE:
        _say_again(said)
        return est
    terms = record_end_terms(est.model_, data.omega, decay_rate=est._shift,
                             record_length=est._record, quantity=data.quantity,
                             cut=est._record_cut)
    with_a2 = a2_unmodelled(est.model_, data.quantity)
    corrected = data._replaced(values=data.values - terms)
    est.__dict__["_end_removed"] = (data.freq_hz, terms, with_a2)
    try:
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            est._fit_weighted(corrected, auto)
    finally:
        est.__dict__.pop("_end_removed", None)
    band = np.isin(data.freq_hz, est.data_.freq_hz)
    est.data_ = est._data_band = data.select(band)
    est.report_ = est.report_.replace(record_end_removed=share)
    _say_again(said)
    return est
