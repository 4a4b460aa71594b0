"""modalid: pole-residue (modal) models of driving-point receptances.

The single model object of the project is :class:`ModalModel`; identification from
measured FRFs builds on it.
"""

from importlib.metadata import PackageNotFoundError as _NotInstalled
from importlib.metadata import version as _version

try:  # one version, pyproject.toml's, for the three packages of the distribution
    __version__ = _version("impactpred")
except _NotInstalled:  # pragma: no cover - imported from a source tree never installed
    __version__ = "0+unknown"

from ._report import FitReport
from .fit import ModalFit, ModalFitWarning
from .frf import FRFData
from .frf_set import FRFSet
from .hammer import (DoubleHitWarning, HammerFRF, correct_exponential_window,
                     find_double_hits, frf_from_hammer)
from .io import read_frf, write_frf
from .io_set import read_frf_set
from .model import ModalModel
from .multi_output import MultiOutputModalModel
from .quantities import QUANTITIES, receptance_to, to_receptance
from .saved_fit import SavedFit
from .shapes import mac, mpc

__all__ = ["ModalFit", "ModalFitWarning", "FRFData", "ModalModel", "QUANTITIES", "receptance_to",
           "to_receptance", "read_frf", "write_frf"]
__all__ += ["HammerFRF", "DoubleHitWarning", "frf_from_hammer", "find_double_hits",
            "correct_exponential_window"]
__all__ += ["MultiOutputModalModel", "FitReport", "SavedFit"]
__all__ += ["FRFSet", "read_frf_set", "mac", "mpc"]
