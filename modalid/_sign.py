"""The sign of a measured FRF: stored with the other convention, or with its sign reversed?

Two facts of a causal, passive structure, read off the data before any fit:

* *Orientation*. Every mode of a causal FRF (this project's ``s = i omega``, Fourier
  kernel ``exp(-i omega t)``) turns clockwise in the complex plane as the frequency rises,
  whatever its modal constant's sign or phase (a constant rotates the loop, it does not
  mirror it). An FRF stored with the other convention (kernel ``exp(+i omega t)``, time
  dependence ``exp(-i omega t)``) is the complex conjugate: its loops turn
  counter-clockwise. The score is the turning of successive lines, weighted by their
  magnitude: ``sum Im(conj(Y_k) Y_{k+1}) / sum |Im(conj(Y_k) Y_{k+1})|`` on the mobility
  ``Y`` (-1: all clockwise, +1: all counter-clockwise).
* *Conductance*. The real part of a passive driving point's mobility is never negative
  (the power it absorbs). The score is ``sum Re Y / sum |Re Y|`` (+1: all positive). A
  driving point whose response was recorded against the force (sign reversed) scores
  near -1; a transfer FRF scores in between.

Both are weighted by the coherence when the file gives it. The thresholds (0.5 for the
orientation, -0.8 for the conductance) leave the measured files of the project well
clear: their causal FRFs turn at -0.65 to -0.99 (one analyzer export +0.13), the transfer
FRFs' conductance lies between -0.44 and +0.12.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .frf import FRFData

__all__ = ["SignCheck", "check_sign"]

#: orientation score above which the FRF is taken as stored with the other convention
TURN_LIMIT = 0.5
#: conductance score below which a driving point is taken as having its sign reversed
CONDUCTANCE_LIMIT = -0.8


@dataclass(frozen=True)
class SignCheck:
    """What :func:`check_sign` found.

    Attributes
    ----------
    turning : float
        Orientation score in [-1, 1]: -1 every loop clockwise (causal, this project's
        convention), +1 counter-clockwise (the complex conjugate).
    conductance : float
        Share in [-1, 1] of the mobility's real part that is positive minus the share
        negative: +1 for a passive driving point, -1 for one with its sign reversed.
    verdict : str
        ``"conjugate"`` (stored with the other convention), ``"reversed"`` (a driving
        point with its sign reversed, or a transfer FRF), or ``"ok"``.
    """

    turning: float
    conductance: float
    verdict: str

    def problem(self, source, *, data: bool = False, applied=()) -> str:
        """One sentence naming ``source``, what is wrong and the reading option that fixes
        it (as ``read_options={...}``; the command line's ``--conjugate``/``--negate``).

        Parameters
        ----------
        source : str
            The file (or data) the check was made on, for the message.
        data : bool, keyword-only
            ``source`` is an :class:`~modalid.FRFData` in memory, not a file: the remedy
            is to conjugate or negate its values.
        applied : iterable of str, keyword-only
            The reading options given (``"conjugate"``, ``"negate"``): where the one the
            check calls for is among them, the remedy is to leave it out (it made the
            problem).

        Returns
        -------
        str
        """
        if self.verdict == "conjugate":
            option, seen = "conjugate", ("its resonances turn counter-clockwise in the "
                                         f"complex plane (turning score {self.turning:+.2f}")
        elif self.verdict == "reversed":
            option, seen = "negate", ("the real part of its mobility is negative "
                                      f"(conductance score {self.conductance:+.2f}")
        else:
            return ""
        transfer = "; if it is a transfer FRF, give the driving point's"
        if option in set(applied) and not data:
            return (f"{source}: read with read_options={{'{option}': True}}, {seen}): read "
                    f"it without read_options={{'{option}': True}}"
                    + transfer * (option == "negate"))
        if option == "conjugate":
            return (f"{source}: {seen}; a causal FRF's turn clockwise, -1): it is stored "
                    "with the other sign convention (Fourier kernel exp(+i w t)), the "
                    "complex conjugate of this project's; "
                    + ("conjugate its values" if data
                       else "read it with read_options={'conjugate': True}"))
        return (f"{source}: {seen}; a passive driving point's is positive, +1): its sign is "
                "reversed (response recorded against the force); "
                + ("negate its values; if its quantity is wrong (an accelerance taken for a "
                   "receptance looks reversed too), correct it" if data else
                   "read it with read_options={'negate': True}; if its quantity is stated "
                   "wrong (an accelerance read as a receptance looks reversed too), read it "
                   "with quantity=... (or correct the quantity the file states)")
                + transfer)


def _scores(frf: FRFData):
    keep = frf.freq_hz > 0
    if np.count_nonzero(keep) < 3:
        return 0.0, 0.0
    data = frf.select(keep)
    y = data.convert("mobility").values
    weight = np.ones(y.size) if data.coherence is None else np.asarray(data.coherence, float)
    turn = np.imag(np.conj(y[:-1]) * y[1:]) * np.sqrt(weight[:-1] * weight[1:])
    real = y.real * weight
    with np.errstate(invalid="ignore", divide="ignore"):
        turning = float(np.sum(turn) / np.sum(np.abs(turn)))
        conductance = float(np.sum(real) / np.sum(np.abs(real)))
    return (turning if np.isfinite(turning) else 0.0,
            conductance if np.isfinite(conductance) else 0.0)


def check_sign(frf: FRFData) -> SignCheck:
    """The orientation and conductance scores of ``frf`` and what they say.

    Parameters
    ----------
    frf : FRFData
        Receptance, mobility or accelerance; lines at 0 Hz are left out.

    Returns
    -------
    SignCheck
        ``verdict`` ``"conjugate"`` when the turning score exceeds 0.5, else
        ``"reversed"`` when the conductance score is below -0.8, else ``"ok"``.
    """
    if not isinstance(frf, FRFData):
        raise TypeError(f"frf must be an FRFData, got {type(frf).__name__}")
    turning, conductance = _scores(frf)
    verdict = ("conjugate" if turning > TURN_LIMIT
               else "reversed" if conductance < CONDUCTANCE_LIMIT else "ok")
    return SignCheck(turning, conductance, verdict)
