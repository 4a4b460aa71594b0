"""modalid: pole-residue (modal) models of driving-point receptances.

The single model object of the project is :class:`ModalModel`; identification from
measured FRFs builds on it.
"""

from .frf import FRFData
from .model import ModalModel
from .quantities import QUANTITIES, receptance_to, to_receptance

__all__ = ["FRFData", "ModalModel", "QUANTITIES", "receptance_to", "to_receptance"]
