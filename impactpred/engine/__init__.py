"""The exact event engine: linear phases in closed form, a certified event search, contact rules.

Both front ends run on it: ``solve_impact(..., method="laplace")``
(:mod:`impactpred.solvers.laplace`: two bodies, one clearance, one contact) and
:meth:`impactpred.damper.ImpactDamper.simulate` (:mod:`impactpred.damper._engine`: a
primary and a free mass, a clearance on both sides, a harmonic load, many cycles). A front
end builds its phases (matrices, output and event rows) from its inputs and shapes the
result; the engine propagates and decides.

Modules, bottom up (no module imports one above it):

* :mod:`.spectral`: the closed form of a phase ``x' = M x`` (nilpotent block + diagonal
  rest), split once per kind of phase; :mod:`.rank_one`: a contact phase as the free
  flight plus the rank-one feedback of the contact force (poles = zeros of
  ``H1 + H2``), used by both front ends' contact phases.
* :mod:`.exp_kernels`: compiled evaluation of sums of exponentials on uniform grids, the
  Hermite bound, root polishing; :mod:`.step_kernels`, :mod:`.search`: the certified
  multilevel event search, the one event search of both loops (compiled; its Python
  oracle is in ``tests/``).
* :mod:`.phase`: a phase with a harmonic load (particular solution) and
  :func:`.phase.search_event`.
* One-sided runs (one clearance, no load): :mod:`.contact_loop` (the relative-degree
  rule both front ends use, the contact-start rules: Dirac impulse, hold or release, a
  phase's run and the compiled loop), :mod:`.impact_run` (the phases, the
  matrix-exponential fallback, the exact force peak).
* Two-sided runs (two stops, harmonic load): :mod:`.cycle_state` (the state and the
  output rows), :mod:`.cycle_loop` (compiled loop for rigid and instantaneous
  contacts, the Zeno rule, the stick-or-separate decision), :mod:`.cycle_compiled` (its
  driver), :mod:`.cycle_run` (the loop with every contact law: spring-dashpot phases,
  Hertz through :mod:`.hertz`), :mod:`.hertz` (time-stepped Hertz contact).

Contact laws themselves are :mod:`impactpred.contact` (``is_linear``, ``is_impulsive``
say how the engine treats them). See ``docs/architecture.md``.
"""

#: most time samples one run holds, the front ends' common cap (before any work, not as a
#: MemoryError): a stepping solver's steps or an exact solver's output samples
#: (``solve_impact``), a damper run's ``n_cycles * samples_per_cycle``
MAX_SAMPLES = 4_000_000
