"""The paper's case (c): a mass strikes the free end of a fixed rod of the same mass.

The force is a sawtooth whose kinks are the rod's wave reflections; the mass leaves
with part of its energy and the rod keeps vibrating. ``impactpred.paper`` holds the
paper's four cases as bodies; the exact Saint-Venant answer comes from
``data_synth.reference_impacts``.
"""
import matplotlib.pyplot as plt

from impactpred import solve_impact
from impactpred.paper import paper_cases

case = {c.key: c for c in paper_cases()}["c"]
res = solve_impact(case.body1, case.body2, t_end=case.t_end)
print(case.description)
print(f"method {res.method}, dt {res.dt:g} s, contacts {res.contact_intervals}")
print(f"restitution {res.restitution:.5f} (Saint-Venant: 0.698876)")

fig, ax = plt.subplots()
res.plot(ax=ax)
ax.set_title("Case (c): 1 kg mass on a fixed rod (1 kg, transit time 1 s)")
fig.tight_layout()
