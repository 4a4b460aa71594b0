"""impactpred: predict the impact of two linear structures from their driving-point dynamics.

The core is the Laplace-transform method: while the bodies touch, the contact force is
``F(s) = (Y10 - Y20)/(H1 + H2)``; its time-domain twin is a convolution equation.
"""

from importlib.metadata import PackageNotFoundError as _NotInstalled
from importlib.metadata import version as _version

try:  # one version, pyproject.toml's, for the three packages of the distribution
    __version__ = _version("impactpred")
except _NotInstalled:  # pragma: no cover - imported from a source tree never installed
    __version__ = "0+unknown"

from .api import METHODS, choose_dt, solve_impact
from .body import Body, SampledResponse
from .contact import ContactLaw, Hertz, LinearSpring, Rigid
from .damper import (BaseExcitation, DamperResult, HarmonicForce, ImpactDamper,
                     InstantaneousImpact)
from .points import PointResponse
from .predict import (BandWarning, ContinuationWarning, IdentificationWarning, Prediction,
                      predict)
from .result import BodyEnergy, EnergyAudit, EnergyWarning, ImpactResult

__all__ = ["Body", "SampledResponse", "solve_impact", "choose_dt", "METHODS", "Rigid",
           "LinearSpring", "Hertz", "ContactLaw", "ImpactResult", "BodyEnergy", "predict",
           "Prediction",
           "BandWarning", "PointResponse"]
__all__ += ["EnergyAudit", "EnergyWarning", "IdentificationWarning", "ContinuationWarning"]
__all__ += ["ImpactDamper", "HarmonicForce", "BaseExcitation", "InstantaneousImpact",
            "DamperResult"]
