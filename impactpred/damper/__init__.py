"""Impact dampers: a free mass between two stops on a vibrating structure.

The primary structure is any grounded, passive driving-point receptance (a
``modalid.ModalModel``, a multi-output model's driving row, or a
``data_synth.SpringMass``); the damper mass strikes it through ``Rigid()``,
``LinearSpring``, ``Hertz`` or the classical :class:`InstantaneousImpact`, under a
harmonic force or base excitation. :meth:`ImpactDamper.simulate` runs an event-driven
engine that is exact between events (closed-form phases, no time steps) for thousands
of forcing cycles.
"""

from ..contact import InstantaneousImpact
from .excitation import BaseExcitation, HarmonicForce
from .masri_caughey import MasriCaugheySolution, masri_caughey, masri_caughey_curve
from .result import DamperResult, DamperState
from .sweep import SweepError, optimum_clearance, plot_optimum_clearance, sweep
from .system import ImpactDamper

__all__ = ["ImpactDamper", "HarmonicForce", "BaseExcitation", "InstantaneousImpact",
           "DamperResult", "DamperState", "masri_caughey", "masri_caughey_curve",
           "MasriCaugheySolution", "sweep", "SweepError", "optimum_clearance",
           "plot_optimum_clearance"]
