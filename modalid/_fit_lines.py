"""Which lines a :class:`modalid.ModalFit` fits, and with which weights: the band (given,
or chosen from the data), a very fine band decimated, the per-line weights given to
``fit`` (or as the setting) cut to the band, else the weights of ``weighting``
(``relative``, ``mixed``, ``noise``, ``uniform``) and the coherence's.

:class:`FitLines` is one of ``ModalFit``'s bases (with
:class:`modalid._frf_pipeline.FRFPipeline`, which calls :meth:`FitLines._prepare` and
reads :meth:`FitLines._relative`); it reads the estimator's settings and sets
``_band_weights``, ``_band_reason``, ``_weighting_on``, ``_noise``,
``_coherence_weight`` and ``data_``.
"""

from __future__ import annotations

import numpy as np

from ._band import band_to_fit, choose_band, choose_weighting, decimation, given_band, noise_model
from ._checks import as_real_array
from ._noise import noise_level
from ._window import check_record_lines
from .quantities import receptance_to

__all__ = ["FitLines"]


class FitLines:
    """The lines and weights of a ``ModalFit`` (a base class; see the module)."""

    def _mixed_weights(self, mag):
        """One over the modelled noise ``sqrt((sigma_rel |H|)^2 + floor^2)`` of each line
        (``weighting="mixed"``; ``mag``: the data's or the model's ``|H|``)."""
        sigma_rel, floor = self._noise
        return 1.0 / np.sqrt((sigma_rel * mag) ** 2 + floor ** 2)

    def _relative(self):
        on = getattr(self, "_weighting_on", self.weighting)
        return on in ("relative", "mixed") and getattr(self, "_line_weights", None) is None

    def _given_weights(self, weights):
        """The per-line weights of this fit, ``fit``'s or the setting's (not both), as a
        finite array checked for sign and all zeros; their length is checked against the
        data in :meth:`_prepare`. None without."""
        if weights is not None and self.weights is not None:
            raise ValueError("weights given twice, as ModalFit(weights=...) and to "
                             "fit(data, weights=...): give them to fit only")
        given = self.weights if weights is None else weights
        if given is None:
            return None
        given = as_real_array("weights", given, ndim=1)
        if np.any(given < 0):
            i = int(np.argmax(given < 0))
            raise ValueError(f"weights must be >= 0, got {float(given[i])!r} at line {i}")
        if not np.any(given > 0):
            raise ValueError(f"weights must not be all 0, got {given.size} zeros")
        return given

    def _prepare(self, data):
        """``(receptance FRFData of the band, weights per line, cut)`` of the FRFData
        ``data``; ``cut``: lines below the band were dropped by ``freq_range``."""
        given = self._line_weights
        if given is not None:
            if given.shape != data.freq_hz.shape:
                raise ValueError(f"weights must be {data.freq_hz.size} values (one per "
                                 f"line of the data), got shape {given.shape}")
            given = given[data.freq_hz > 0]
        data = data.select(data.freq_hz > 0)
        if self._record is not None:
            check_record_lines(data.freq_hz, self._record)
        first = data.freq_hz[0]
        def automatic():                              # the lines the data can vouch for
            # an exponential window's model describes the low end (its mass line); a
            # record end's terms alone are smooth, and rough lowest lines are noise
            return choose_band(data, low_end=not self._shift)

        band, self._band_reason = (automatic() if self.freq_range is None
                                   else given_band(self.freq_range, automatic))
        if given is not None:
            lo, hi = band
            given = given[(data.freq_hz >= lo) & (data.freq_hz <= hi)]
            if not np.any(given > 0):
                raise ValueError(f"weights must not be all 0 on the band fitted ({lo:g}-"
                                 f"{hi:g} Hz)")
        data = band_to_fit(data, band)
        step, why = decimation(data.values)           # a very fine band: every step-th line
        if step > 1:
            data = data.select(slice(None, None, step))
            given = None if given is None else given[::step]
        if why:
            self._band_reason = f"{self._band_reason}; {why}"
        self._band_weights = self.weights_ = given    # per line of the band, or None
        # lines below the band were dropped by the user (the automatic band drops only
        # lines that scatter like noise: the data still reach below the first resonance)
        cut = (self.freq_range is not None and self.freq_range[0] is not None
               and bool(data.freq_hz[0] > first))
        self._data_band = self.data_ = data           # in the data's own quantity
        if self.weighting == "auto":      # a refit (FitOne._fit_weighted) forces its own
            self._weighting_on, self._weighting_reason = (
                self.__dict__.get("_weighting_forced") or choose_weighting(data.values))
        frf = data.to_receptance()
        mag = np.abs(frf.values)
        # the noise is estimated in the quantity measured, where it is closest to
        # stationary (an accelerometer's floor is one of accelerance; in receptance it
        # grows like 1/omega^2 towards the band's low end), then carried to receptance
        to_data = np.abs(receptance_to(data.quantity, np.ones(frf.omega.size), frf.omega))
        self._noise = None          # noise_model in receptance, when a step needs it
        if self._weighting_on == "relative":
            w = 1.0 / np.maximum(mag, 1e-12 * mag.max())
        elif self._weighting_on == "noise":
            w = to_data / noise_level(data.values)
        elif self._weighting_on == "mixed":
            sigma_rel, floor = noise_model(data.values)
            self._noise = sigma_rel, floor / to_data
            w = self._mixed_weights(mag)
        else:
            w = np.full(mag.size, 1.0 / np.sqrt(np.mean(mag**2)))
        self._coherence_weight = (1.0 if frf.coherence is None
                                  else np.sqrt(np.clip(frf.coherence, 1e-3, 1.0)))
        if given is not None:      # error in the data's quantity -> in receptance
            w = given * to_data
            scale = np.sqrt(np.mean((w * mag) ** 2))
            return frf, w / (scale if scale > 0 else 1.0), cut
        return frf, w * self._coherence_weight, cut
