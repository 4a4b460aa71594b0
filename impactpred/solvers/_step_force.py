"""The contact force of each step of the zero-order-hold solvers (``"convolution"``, and
``"modal"`` where it holds the force constant over a step): the contact law's own
complementarity, or, for a rigid contact between bodies that are masses at the contact,
a plastic start and a held gap (:class:`StepForce`)."""

from __future__ import annotations

import warnings

import numpy as np

__all__ = ["MASS_LIKE_RATIO", "StepForce", "backward_gap", "kernel_ratio", "rounding_gap"]

#: ``dS[1]/dS[0]`` of the pair's summed kernel above which the bodies are masses at the
#: contact: a pure mass gives 3 (``S = t^2/2m``), a wave impedance (``h(0+) > 0``, a rod)
#: 1, a beam's ``h ~ sqrt(t)`` 1.83, a flexibility term about 0
MASS_LIKE_RATIO = 2.5

#: the fraction of the step at which :func:`kernel_ratio` looks at the bodies' small-time
#: response (what they are at the contact, whatever the step resolves)
SMALL_TIME = 1e-2


def kernel_ratio(step_responses, dt: float) -> tuple:
    """``(dS[1]/dS[0] at the step, the same at SMALL_TIME dt)`` of a pair of bodies.

    Parameters
    ----------
    step_responses : sequence of callables
        Each body's step response ``S(t)`` (m/N) of an array of times (s).
    dt : float
        Step (s).
    """
    times = np.array([dt, 2 * dt, SMALL_TIME * dt, 2 * SMALL_TIME * dt])
    s = np.sum([np.asarray(f(times), dtype=float) for f in step_responses], axis=0)
    return ((s[1] - s[0]) / s[0] if s[0] > 0 else 0.0,
            (s[3] - s[2]) / s[2] if s[2] > 0 else 0.0)


class StepForce:
    """The contact force of each step of the zero-order-hold solvers.

    ``force(G, g_prev, g_before)`` gives ``f_n`` (N) from the gap ``G`` (m) the step
    would end with at no force, the gap ``g_prev`` at its start and ``g_before`` one step
    earlier; the law's own :meth:`~impactpred.contact.ContactLaw.step_force` does it,
    except for ``Rigid`` contact between bodies that are masses at the contact: the
    pair's kernel ratio ``dS[1]/dS[0]`` above :data:`MASS_LIKE_RATIO` both at the step
    and at a hundredth of it (``h1(0+) + h2(0+) = 0`` and no flexibility term: two lumped
    masses, a truncated modal model without its residual flexibility; a flexibility term
    seen as a mass by a coarse step keeps the law's rule).

    There the exact force starts with a plastic Dirac impulse (method.md, sections 1 and
    5: undamped bodies lose energy at the Dirac parts only), and the law's
    ``f = -G/K0``, which closes the gap within the step, sends the bodies apart at about
    the speed they met (a constant force that stops a mass within a step sends it back):
    a rebound of restitution up to 1. The step of such a contact's start takes the
    plastic impulse instead, the force that zeroes the relative velocity at the step's
    end: ``f = -v/S'(dt)``, with ``v`` the force-free end velocity from the last three
    gaps, ``(3 G - 4 g_prev + g_before)/(2 dt)`` (exact under a constant acceleration),
    and ``S'(dt) = (5 dS[0] + dS[1])/(4 dt)`` the velocity a unit force gives over the
    step (exact for ``S = a t^2 + b t^3``; ``2 dS[0]/dt`` for masses). The gap it ends
    with, ``g_prev + v dt/2``: within half a step's travel of 0, either side (inside the
    bodies, or a gap across which the force acts), is held while the contact presses
    (``f = (g_held - G)/K0``: the bodies stick where they met).

    A held gap leaves the velocity the start step could not take away alternating in
    sign step to step (the hold's neutral mode ``v_{n+1} = -v_n``), and the force with
    it: the bodies part when holding them would pull on two steps running (a single
    step's dip is that mode, and the step is held at no force). They touch again at the
    gap they parted at, ``g_touch``, until the gap has passed ``|g_touch|`` above 0
    (``2 g_touch`` for a positive one), and at 0 after: the offset does not carry from
    contact to contact. A touch again before that is the same contact (a parting within
    the offset is below the step's resolution): ``holding``, per step, whether a contact
    held (its force may be 0), marks the steps between as held. A contact that starts at
    rest under a constant acceleration gets the law's force (the two rules agree there).
    First order in ``dt``, like the zero-order hold at every event. ``starts`` lists the
    steps that took a plastic impulse (:func:`._stepping.assemble_result` reports each as
    a Dirac impulse, not as a force of impulse/dt).

    Parameters
    ----------
    contact : ContactLaw
    k0, k1 : float
        ``dS[0]``, ``dS[1]`` of the pair's summed kernel (m/N).
    dt : float
        Step (s).
    small_time_ratio : float or None, keyword-only
        ``dS[1]/dS[0]`` at ``SMALL_TIME dt`` (:func:`kernel_ratio`); None: not checked.
    gap_tolerance : float, keyword-only
        Gap (m) below which a plastic contact's press or approach is rounding (the
        history sums' error in the difference of two displacements): after a plastic
        impact of two free masses the force needed is 0, and rounding must not keep them
        "in contact" or start another impact (:func:`rounding_gap`).
    """

    def __init__(self, contact, k0: float, k1: float, dt: float, *, small_time_ratio=None,
                 gap_tolerance=0.0):
        from ..contact import Rigid

        self.k0, self.dt, self._law = float(k0), float(dt), contact
        self.plastic = (type(contact) is Rigid and k1 > MASS_LIKE_RATIO * k0
                        and (small_time_ratio is None or small_time_ratio > MASS_LIKE_RATIO))
        # the velocity per unit force over a step, as a gap change: S'(dt) dt/2 (m/N)
        self._k_velocity = (5.0 * k0 + k1) / 8.0
        self.gap_tolerance = float(gap_tolerance)
        self._held: float | None = None    # the gap held while a plastic contact presses
        self._press = 0.0                  # the last step's press (m)
        self._touch = 0.0                  # the gap at which the bodies touch
        self._reopen = np.inf              # the gap past which that is 0 again
        self.impacts = 0                   # plastic starts (re-touches within a contact too)
        self.starts: list = []             # the steps at which they happened
        self.holding: list = []
        self._parted = 0                   # the step at which the last hold parted

    def force(self, G: float, g_prev: float, g_before: float) -> float:
        """``f_n`` (N) of the next step; see the class docstring."""
        if not self.plastic:
            return self._law.step_force(G, self.k0, g_prev, self.dt)
        f = self._plastic(G, g_prev, g_before)
        self.holding.append(self._held is not None)
        return f

    def _plastic(self, G, g_prev, g_before):
        tol = self.gap_tolerance
        if self._held is not None:
            press, last = self._held - G, self._press
            self._press = press
            if press > tol:
                return press / self.k0
            if press + last > 2.0 * tol:   # a one-step dip: the hold's alternating mode
                return 0.0
            touch = self._held                     # holding would pull: they part
            self._touch, self._reopen, self._held = touch, max(touch, 0.0) + abs(touch), None
            self._parted = len(self.holding)
            return 0.0
        if G > self._reopen:                       # opened past the offset: touch at 0
            self._touch, self._reopen = 0.0, np.inf
        if G >= self._touch:
            return 0.0
        # -v dt/2 with v the force-free end velocity: what the impulse must take away
        approach = -(3.0 * G - 4.0 * g_prev + g_before) / 4.0
        if approach <= tol:                        # inside, but not closing at the end
            return 0.0
        f = approach / self._k_velocity
        if np.isfinite(self._reopen):              # touched again within the offset:
            self.holding[self._parted:] = [True] * (len(self.holding) - self._parted)
        self._held, self._press = G + self.k0 * f, 0.0
        self.impacts += 1
        self.starts.append(len(self.holding))
        return f

    def unresolved_notes(self, n_contacts: int, *, stacklevel: int) -> tuple:
        """``(message,)`` when the plastic holds parted and touched again on rounding
        (also warned, ``RuntimeWarning`` at ``stacklevel``), else ``()``.

        A hold resolves a force only to ``gap_tolerance / K0`` (N): ``K0`` falls like
        ``dt^2`` for masses, the gaps' rounding does not. Below that the bodies part and
        touch again within what the result reports as one contact (its openings stay
        within rounding of the held gap); more than ``2 n_contacts + 10`` plastic starts
        for ``n_contacts`` contacts says so (a mass pressed by a 1 N spring over 10^5
        steps of 0.2 us: the convolution solver's sums resolve 0.3 N, 565 starts).
        """
        if not self.plastic or self.impacts <= 2 * n_contacts + 10:
            return ()
        said = (f"dt={self.dt:.3g} s is too fine for a rigid contact between masses: the "
                f"step resolves the contact force to {self.gap_tolerance / self.k0:.3g} N "
                f"only (the gaps' rounding over the step's {self.k0:.3g} m/N; the bodies "
                f"touched {self.impacts} times in {n_contacts} contacts): use a coarser "
                "dt (dt=None picks one) or method='laplace'")
        warnings.warn(said, RuntimeWarning, stacklevel=stacklevel + 1)
        return (said,)


def backward_gap(gap0: float, free1: float, free2: float | None) -> float:
    """The gap one step before ``t_0`` (m) on the quadratic through the force-free gaps
    at ``t_0, t_1, t_2``: :class:`StepForce`'s ``g_before`` at the first step. With no
    ``t_2`` (``free2=None``, a single step) the line through the first two."""
    if free2 is None:
        free2 = 2.0 * free1 - gap0
    return 3.0 * gap0 - 3.0 * free1 + free2


def rounding_gap(y1, y2) -> float:
    """Gap (m) within which a step's predicted gap is rounding: ``1e-12`` of the largest
    displacement (the FFT history sums of the convolution solver err by up to about
    ``1e-12`` of it after a plastic impact; a contact's own press one step after its
    impact is 1e-11 of it and more on the test cases). :class:`StepForce`'s tolerance."""
    return 1e-12 * max(float(np.max(np.abs(y1))), float(np.max(np.abs(y2))), 1e-300)
