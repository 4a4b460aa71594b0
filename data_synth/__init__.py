"""data_synth: exact driving-point models of simple structures, for synthetic data and tests.

Each model gives its exact receptance ``H(s)`` (m/N), impulse and step responses, natural
frequencies and a truncated :class:`modalid.ModalModel` (method.md section 2):

* :class:`LumpedMass` - a free rigid mass;
* :class:`SpringMass` - a grounded spring-mass(-damper);
* :class:`Rod` - a uniform rod in axial vibration, free or fixed far end, struck at one end;
* :class:`CantileverBeam` - an Euler-Bernoulli cantilever struck at its free tip;
* :func:`cantilever_roots` - roots of ``1 + cosh(e) cos(e) = 0``;
* :func:`example_data_path` - the measured example files of ``tests/data``, from any directory.
* :func:`random_modal_model` - many well-separated modes at random frequencies.
"""

from importlib.metadata import PackageNotFoundError as _NotInstalled
from importlib.metadata import version as _version

try:  # one version, pyproject.toml's, for the three packages of the distribution
    __version__ = _version("impactpred")
except _NotInstalled:  # pragma: no cover - imported from a source tree never installed
    __version__ = "0+unknown"

from ._base import ExactModel
from ._files import example_data_path
from .beam import CantileverBeam
from .lumped import LumpedMass, SpringMass
from .measure import (HammerTest, lightly_damped, synthetic_frf, synthetic_hammer_test,
                      synthetic_impulse_response)
from .random_modes import random_modal_model
from .rod import Rod
from .roots import cantilever_roots

__all__ = ["ExactModel", "LumpedMass", "SpringMass", "Rod", "CantileverBeam",
           "cantilever_roots"]
__all__ += ["synthetic_frf", "lightly_damped", "synthetic_impulse_response",
            "synthetic_hammer_test", "HammerTest", "example_data_path", "random_modal_model"]
