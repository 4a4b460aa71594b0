"""How ``ModalFit`` fits one FRF: the weighting, and the driving-point decision of
``passive="auto"``.

:class:`FitOne` is a mixin of :class:`modalid.ModalFit`. :meth:`FitOne._fit_weighted`
runs :meth:`FitOne._fit_passive_choice` and, under ``weighting="auto"``, refits with one
over the data's own scatter a fit weighted ``1/|H|`` that failed, found no passive fit
of a driving point or missed a resonance of the data; :meth:`FitOne._fit_passive_choice`
fits with the passivity constraint given, or (``passive="auto"``) lets an unconstrained
fit decide whether the FRF is a driving point (the quick probe, or the full fit where the
probe misses lines or calls it a transfer FRF that the full fit does not) and refits
passive where it is.
"""

from __future__ import annotations

import sys
import warnings

import numpy as np

from ._frf_pipeline import ModalFitWarning
from ._segment_assembly import resume_probe
from ._verdict import (driving_point_decision, judged_report, line_error_tolerance,
                       misfit_suspect)

__all__ = ["FitOne"]


class FitOne:
    """Mixin of :class:`modalid.ModalFit`: one FRF's fit (see the module docstring)."""

    def _fit_weighted(self, data, auto: bool):
        """Fit ``data`` (:meth:`_fit_passive_choice`) and return self.

        Under ``weighting="auto"`` (no per-line weights), a fit weighted ``1/|H|``
        (maximum likelihood for noise proportional to the FRF) that failed, that
        ``passive="auto"`` found no passive driving point for want of a passive fit (its
        modes' strength positive, the passive fit stalled), that missed a resonance of the
        data (``report_["missed_resonances_hz"]``,
        :func:`modalid._verdict.missed_resonances`) or that is "suspect" for its error
        otherwise (:func:`modalid._verdict.misfit_suspect`) is refitted weighted by one
        over the data's own scatter
        (:func:`modalid._lsfd.noise_level`, smoothed over the lines around: a sharp peak
        keeps the weight of its surroundings). The refit stands unless it fails too or
        misses the lines by more (median relative error per line, in the data's quantity;
        up to the verdict's tolerance it may); after a stall it must be a driving point
        with as many modes (or fewer resonances missed, the strong modes kept), for a
        missed resonance miss fewer, for a suspect fit be "ok" (:func:`_refit_stands`).
        ``report_["weighting_reason"]`` says which fit stands and why, and the warnings
        said are those of the fit that stands.

        Where a mode's evidence lies in one or two lines, weights ``1/|H|`` give those
        lines little say: a cantilever's mobility from 3 times its first mode (3 %
        noise, modes far narrower than the lines, one 40 times its neighbours) lost its
        two lowest modes and its pseudo-modes cancelled to a model near zero below 50 Hz
        (error 95 %, failed); refitted, all ten modes at 0.4 %. A cantilever's
        accelerance with under-resolved lowest modes (0.16 Hz for 0.21, 2.0 Hz at damping
        0.23 for 1.32) stalled passive at 15.8 % median error against 3.6 %; refitted, a
        passive driving point at 2.6 %. A fixed rod's exact FRF at zeta 1e-2, failed for
        an infinite modal mass at 0.8 % error, keeps its fit rather than a refit at 29 %.
        """
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            self._fit_passive_choice(data, auto)
        said = self._refit_low_end(data, auto, said)
        stalled = self.__dict__.pop("_passive_stalled", False)
        verdict, missed = self.report_["verdict"], self.report_["missed_resonances_hz"]
        trigger = ("failed" if verdict == "failed" else "stalled" if stalled
                   else "missed" if missed
                   else "suspect" if verdict == "suspect" and misfit_suspect(self.report_)
                   else None)
        if (self.weighting == "auto" and self._weighting_on == "relative"
                and self._line_weights is None and trigger):
            first = dict(self.__dict__)
            if trigger in ("failed", "suspect"):
                why = (f"{'failed' if trigger == 'failed' else 'was suspect'} "
                       f"({'; '.join(self.report_['verdict_reasons'])})")
            elif trigger == "stalled":
                why = f"was no passive driving point ({self.report_['driving_point_reason']})"
            else:
                why = ("missed the data's resonance at "
                       + ", ".join(f"{f:.6g}" for f in missed) + " Hz")
            self.__dict__["_weighting_forced"] = (
                "noise", f"the fit weighted 1/|H| {why}: weighted by the data's own scatter "
                "instead")
            refit = None
            try:
                with warnings.catch_warnings(record=True) as retried:
                    warnings.simplefilter("always")
                    self._fit_passive_choice(data, auto)
                refit = self.report_
            except (ValueError, np.linalg.LinAlgError):
                pass                              # the first fit stands
            finally:
                self.__dict__.pop("_weighting_forced", None)
                self.__dict__.pop("_passive_stalled", None)
            if not _refit_stands(first["report_"], refit, trigger=trigger):
                self.__dict__.clear()             # the first fit stands
                self.__dict__.update(first)
                self.report_ = self.report_.replace(weighting_reason=(
                    f"{self.report_['weighting_reason']}; a refit weighted by the data's own "
                    "scatter did no better"))
            else:
                said = retried
        _say_again(said)
        return self

    def _refit_low_end(self, data, auto: bool, said):
        """A fit whose model misses the band's lowest lines
        (``report_["missed_low_end_hz"]``) with no term for what lies below the band (no
        mass line, no lower residual; ``rigid_body="auto"``, ``"lower"`` among the
        residuals) is refitted with the lower residual pseudo-mode, which stands where it
        no longer misses them and has not failed. pyuff's point 1 (a transfer FRF, first
        peak 51.5 Hz) from 20 Hz missed 20-37 Hz by 51-83 % ("suspect"); with the lower
        residual, "ok" at 2.7 %. Returns the warnings of the fit that stands (``said``:
        the first's)."""
        report = self.report_
        if (report.get("missed_low_end_hz") is None or report["rigid_body"]
                or report["lower_residual_mode"] or not isinstance(self.rigid_body, str)
                or "lower" not in self.residuals):
            return said
        first = dict(self.__dict__)
        self.__dict__.pop("_passive_stalled", None)
        self.__dict__["_lower_forced"] = True
        try:
            with warnings.catch_warnings(record=True) as again:
                warnings.simplefilter("always")
                self._fit_passive_choice(data, auto)
        except (ValueError, np.linalg.LinAlgError):
            again = None
        finally:
            self.__dict__.pop("_lower_forced", None)
        if (again is None or self.report_.get("missed_low_end_hz") is not None
                or self.report_["verdict"] == "failed"):
            self.__dict__.clear()                 # the first fit stands
            self.__dict__.update(first)
            return said
        self.report_ = self.report_.replace(notes=list(self.report_["notes"]) + [
            "refitted with the lower residual: without it the model missed the band's "
            f"lowest lines ({report['missed_low_end_hz'][0]:.6g}-"
            f"{report['missed_low_end_hz'][1]:.6g} Hz)"])
        return again

    def _fit_passive_choice(self, data, auto: bool):
        """Fit ``data`` with the passivity constraint given, or (``auto``) decide it: a
        quick unconstrained probe (or the full unconstrained fit where the probe does not
        suffice) decides from its modes whether the FRF is a driving point
        (:func:`modalid._verdict.driving_point_decision`), and the passive fit follows
        where it is; returns self, judged (``_judge``)."""
        if not auto:
            self._fit_frf(data)
            return self._judge(driving_point=self._passive_on,
                               reason=f"passive={self.passive!r} given")
        # a quick unconstrained probe decides; one full identification follows
        self._passive_on, self.__dict__["_probe"] = False, True
        self.__dict__["_stabilization_cache"] = None     # the passes share the diagram
        try:
            self._fit_frf(data)
        finally:
            del self.__dict__["_probe"]
        full = self._segment_count == 1 and not self._probe_suffices()
        if full:
            # the probe (stable poles, no missed-mode search) missed what the band
            # holds: the full unconstrained fit decides (the hammer test on 4000-4600
            # Hz: eight modes found by the search, a transfer FRF; taken as a driving
            # point for want of evidence, the passive fit had dropped them all)
            unconstrained = self._fit_recorded(data)
        driving, reason = driving_point_decision(self.report_["modes"],
                                                 self._raw_inverse_mass, data=self._data_band)
        probe_reason = reason
        if not full:        # the counts are the probe's, not the final table's modes
            reason = f"the quick unconstrained fit's {reason}"
        probe_error = self.report_["frf_median_relative_error"]
        self._passive_on, refit_said = driving, []
        if full and not driving:
            for w in unconstrained:           # the unconstrained fit stands
                warnings.warn(w.message, w.category, stacklevel=4)
        else:
            # the full fit, its warnings said if it stands (by segments too: it refines
            # the pseudo-modes, which the probe leaves where they were placed)
            refit_said = self._fit_recorded(data)
            if not driving:
                # the probe's junk poles can carry the sign: the full fit decides (a
                # free rod at 1 % noise: two at damping 0.5-0.6 and modal mass -0.12,
                # -1.1, 29 % of the strength; the full fit's 11 modes all positive)
                driving, full_reason = driving_point_decision(
                    self.report_["modes"], self._raw_inverse_mass, data=self._data_band)
                if driving:
                    full = True                   # the full fit's error is the reference
                    reason = (f"{full_reason} (the full unconstrained fit; the quick "
                              f"probe's modes had said: {probe_reason})")
                    probe_error = self.report_["frf_median_relative_error"]
                    self._passive_on = True
                    refit_said = self._fit_recorded(data)
        error = self.report_["frf_median_relative_error"]
        if driving and error > 1.5 * probe_error + 0.01 and not self._passes_as_judged():
            self._passive_on = False          # the data contradict a passive model,
            self._fit_frf(data)               # or the passive fit stalled
            stalled = (f"the passive fit's median error per line is {100 * error:.3g} "
                       f"% against {100 * probe_error:.3g} % for "
                       f"{'the full' if full else 'a quick'} unconstrained one")
            if self._shift == 0 and self.model_.is_passive():
                reason = (f"{reason}; {stalled}, which satisfies the passivity "
                          "constraint itself and stands")
            else:
                driving, reason = False, (f"{reason}, but {stalled}: not a passive "
                                          "driving point")
                self.__dict__["_passive_stalled"] = True
        else:
            for w in refit_said:
                warnings.warn(w.message, w.category, stacklevel=4)
        self.__dict__.pop("_stabilization_cache", None)
        self.__dict__.pop("_probe_assembly", None)
        return self._judge(driving_point=driving, reason=reason)

    def _passes_as_judged(self) -> bool:
        """Whether the passive fit just made is "ok" by the verdict's own standard: then
        the data do not contradict a passive model, though an unconstrained one fits
        their noise closer (a cantilever at 5 % noise, scatter 6.2 %: 16.6 % against
        10.0 % for an unconstrained fit with a noise mode of -203 kg, which was taken,
        "ok", and refused as a transfer FRF by ``impactpred``)."""
        return self._judged_report(driving_point=True, reason="")["verdict"] == "ok"

    def _fit_recorded(self, data) -> list:
        """``_fit_frf(data)`` with its warnings recorded, not said: the caller says them
        if the fit stands."""
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            if not self._passive_on and "_probe_assembly" in self.__dict__:
                resume_probe(self)          # a segmented probe's band, refined
            else:
                self._fit_frf(data)
        return said

    def _probe_suffices(self) -> bool:
        """Whether the quick unconstrained probe's modes can decide the driving point: it
        found a resonance and its median line error is within the verdict's tolerance
        (:func:`modalid._verdict.line_error_tolerance`: no modes missing)."""
        report = self.report_
        tolerance = line_error_tolerance(report["noise_median_relative"])
        return len(report["modes"]) > 0 and report["frf_median_relative_error"] <= tolerance

    def _judge(self, *, driving_point, reason):
        """Add the driving-point decision, damping resolution and the quality verdict
        to ``report_`` (:func:`modalid._verdict.judged_report`); warn
        (:class:`ModalFitWarning`) unless the verdict is ``"ok"``."""
        self.report_ = self._judged_report(driving_point=driving_point, reason=reason)
        if self.report_["verdict"] != "ok":
            warnings.warn(f"the fit is {self.report_['verdict']}: "
                          + "; ".join(self.report_["verdict_reasons"]), ModalFitWarning,
                          stacklevel=3)
        asked, found = self._selection().get("n_modes"), len(self.report_["modes"])
        if asked is not None and found < asked:
            # select_poles keeps at most the diagram's clusters, the checks drop more: a
            # beam's n_modes=8, 12 or 20 all gave its 5, silently (walkthrough)
            note = (f"n_modes={asked} asked, {found} found: the band's stabilization "
                    "diagram and the checks after it support no more")
            self.report_ = self.report_.replace(notes=[*self.report_["notes"], note])
            warnings.warn(note, ModalFitWarning, stacklevel=3)
        return self

    def _judged_report(self, *, driving_point, reason):
        """``report_`` judged (:func:`modalid._verdict.judged_report`), not stored."""
        return judged_report(
            self.report_, self.model_, getattr(self, "frf_", None),
            driving_point=driving_point, reason=reason, weighting=self._weighting_on,
            weighting_reason=self._weighting_reason,
            band_reason=getattr(self, "_band_reason", None))


def _refit_stands(first, refit, *, trigger: str) -> bool:
    """Whether the refit weighted by the data's scatter (report ``refit``, None if it
    raised) replaces the fit weighted ``1/|H|`` (report ``first``).

    ``trigger``: why it was refitted: the first ``"failed"``, its passive fit
    ``"stalled"``, it ``"missed"`` a resonance of the data, or it was ``"suspect"`` for
    its error. The refit must not fail; after a stall it must be a driving point with as
    many modes as the first, or fewer of the data's resonances missed and every strong
    positive mode of the first kept (:func:`_strong_modes_kept`; a fixed rod's undamped
    FRF: 10 modes, exact, for the first's 15 that missed 6 of them), for a
    missed resonance miss fewer, for a suspect fit be "ok"; and its median relative
    error per line may not exceed the first's or the verdict's tolerance
    (:func:`modalid._verdict.line_error_tolerance`, the error at which modes count as
    missing), the larger.

    Weighted by the scatter, a sharp peak's own lines count for more than the median
    line: a cantilever's accelerance at 3 % noise, 0.7276 Hz where 1/|H| put 0.7055 Hz,
    at 2.58 % median error against 2.53 %; vibration_toolbox's case2 on 100-300 Hz,
    192.39 Hz alone at a median error of 51.63 % (FRF error 68.6 %) against 119.9 and
    192.7 Hz, failed, at 51.56 % (103 %), its scatter 59 %. A fixed rod's exact FRF at
    zeta 1e-2 keeps its failed fit at 0.8 % against a refit's 29 %. After a stall: a
    fixed rod's accelerance from above its second mode (3 % noise, 4 modes) whose passive
    fit stalled at 21.5 % against 6.4 % is refitted a passive driving point at 6.9 %, its
    4 modes (refused before); a fixed rod's receptance whose passive fit stalled at 5.5 %
    against 2.5 % was refitted at 4.6 % without the mode 1.4 lines below the band's top,
    and predicted a restitution of -0.69 for the exact 0.92: refused.
    """
    if refit is None or refit["verdict"] == "failed":
        return False
    if trigger == "suspect" and refit["verdict"] != "ok":
        return False
    if trigger == "stalled" and (not refit["driving_point"] or (
            len(refit["modes"]) < len(first["modes"])
            and (len(refit["missed_resonances_hz"]) >= len(first["missed_resonances_hz"])
                 or not _strong_modes_kept(first["modes"], refit["modes"])))):
        return False
    if trigger == "missed" and (len(refit["missed_resonances_hz"])
                                >= len(first["missed_resonances_hz"])):
        return False
    allowed = max(first["frf_median_relative_error"],
                  line_error_tolerance(first["noise_median_relative"]))
    return refit["frf_median_relative_error"] <= allowed


def _strong_modes_kept(first, refit) -> bool:
    """Whether every mode of the table ``first`` with a positive modal mass and at least
    a tenth of its strongest mode's strength ``1/|m|`` has a mode of ``refit`` within 2 %
    in frequency (a mode at the band's edge counts as missed by no resonance test)."""
    strength = 1.0 / np.abs(first["modal_mass"].to_numpy(float))
    strong = (first["modal_mass"].to_numpy(float) > 0) & (strength >= 0.1 * strength.max())
    kept = refit["frequency_hz"].to_numpy(float)
    return all(kept.size and np.min(np.abs(kept - f)) <= 0.02 * f
               for f in first["frequency_hz"].to_numpy(float)[strong])


def _say_again(caught) -> None:
    """Say the recorded warnings again: those meant for the user (``UserWarning``s, e.g.
    :class:`ModalFitWarning`) at the caller of ``ModalFit.fit``, the others (numerical
    ``RuntimeWarning``s and the like) where they were raised, under their module's name,
    so that filters by module (``error::RuntimeWarning:modalid.*``) still apply."""
    # file -> module name, built only when a warning needs it (over the 4000 modules
    # loaded it cost 3 ms a fit, and a segmented fit makes one per segment)
    modules = None
    for w in caught:
        if issubclass(w.category, UserWarning):
            warnings.warn(w.message, w.category, stacklevel=4)
        else:
            if modules is None:
                modules = {getattr(module, "__file__", None): name
                           for name, module in list(sys.modules.items())}
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno,
                                   module=modules.get(w.filename))
