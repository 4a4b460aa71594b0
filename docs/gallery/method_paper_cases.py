"""The paper's four cases: the contact forces (case (b) with equal masses)."""
import matplotlib.pyplot as plt

from impactpred import solve_impact
from impactpred.paper import paper_cases

cases = [c for c in paper_cases() if c.key != "b_equal_material"]
fig, axes = plt.subplots(2, 2, figsize=(7.0, 4.4), sharex=True)
for ax, case in zip(axes.flat, cases):
    res = solve_impact(case.body1, case.body2, t_end=case.t_end)
    ax.plot(res.t, res.force)
    ax.set_title(f"({case.key[0]}) e = {res.restitution:.3f}", fontsize=9)
for ax in axes[1]:
    ax.set_xlabel("time (s)")
for ax in axes[:, 0]:
    ax.set_ylabel("force (N)")
fig.tight_layout()
