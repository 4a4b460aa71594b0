"""The result plots: force and motion on twin axes with their zeros level, legends that
hide no curve, units in the labels (impactpred._plot_axes and the ``plot`` methods of
ImpactResult, DamperResult and PointResponse)."""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from data_synth import LumpedMass, Rod, SpringMass  # noqa: E402
from impactpred import Body, LinearSpring, solve_impact  # noqa: E402
from impactpred._plot_axes import align_zeros, legend_above_data  # noqa: E402
from impactpred.damper import HarmonicForce, ImpactDamper, InstantaneousImpact  # noqa: E402


def _zero_height(ax):
    low, high = ax.get_ylim()
    return -low / (high - low)


def _legend_hides_nothing(ax):
    """No data point of any line of the figure lies under ``ax``'s legend, as drawn."""
    figure = ax.figure
    figure.tight_layout()
    figure.canvas.draw()
    box = ax.get_legend().get_window_extent()
    checked = 0
    for each in figure.axes:
        for line in each.get_lines():
            if line.get_label().startswith("_"):        # the zero line
                continue
            xy = line.get_transform().transform(
                np.column_stack([line.get_xdata(), line.get_ydata()]).astype(float))
            inside = ((xy[:, 0] >= box.x0) & (xy[:, 0] <= box.x1)
                      & (xy[:, 1] >= box.y0) & (xy[:, 1] <= box.y1))
            assert not inside.any(), f"{line.get_label()} under the legend"
            checked += 1
    return checked


# ------------------------------------------------------------------------- the helpers
@pytest.mark.parametrize("first, second", [((0.0, 2.0), (-3.0, 1.0)), ((-1.0, 4.0), (-1.0, 9.0)),
                                           ((0.5, 2.0), (-5.0, -1.0))])
def test_align_zeros_levels_the_zeros_and_only_widens(first, second):
    fig, ax = plt.subplots()
    twin = ax.twinx()
    ax.set_ylim(*first)
    twin.set_ylim(*second)
    align_zeros(ax, twin)
    assert _zero_height(ax) == pytest.approx(_zero_height(twin), abs=1e-12)
    for axis, (low, high) in ((ax, first), (twin, second)):
        new_low, new_high = axis.get_ylim()
        assert new_low <= min(low, 0.0) and new_high >= max(high, 0.0)
    plt.close(fig)


def test_align_zeros_with_everything_below_zero():
    fig, ax = plt.subplots()
    twin = ax.twinx()
    ax.set_ylim(-2.0, -1.0)
    twin.set_ylim(-8.0, -3.0)
    align_zeros(ax, twin)
    assert ax.get_ylim() == (-2.0, 0.0) and twin.get_ylim() == (-8.0, 0.0)
    plt.close(fig)


def test_legend_above_data_keeps_aligned_zeros_and_clears_the_curves():
    fig, ax = plt.subplots(figsize=(6, 3))
    t = np.linspace(0.0, 1.0, 400)
    ax.plot(t, np.sin(6 * t) + 1.0, label="a")          # reaches the top right corner
    twin = ax.twinx()
    twin.plot(t, -3 * np.cos(9 * t), "C1", label="b")
    align_zeros(ax, twin)
    before = _zero_height(ax)
    legend_above_data(ax, *[sum(x, []) for x in zip(ax.get_legend_handles_labels(),
                                                     twin.get_legend_handles_labels())],
                      axes=(twin,))
    assert _zero_height(ax) == pytest.approx(_zero_height(twin), abs=1e-12)
    assert _zero_height(ax) < before                    # room made above, zero lower
    assert _legend_hides_nothing(ax) == 2
    plt.close(fig)


# ------------------------------------------------------------------- the result plots
def test_impact_plot_force_and_motion_zeros_level_legend_clear():
    res = solve_impact(Body(LumpedMass(1.0), velocity=1.0),
                       Body(Rod(1.0, 1.0, support="fixed")), gap=0.0, t_end=8.0)
    ax = res.plot()
    motion = [a for a in ax.figure.axes if a is not ax][0]
    assert ax.get_ylabel() == "contact force (N)" and ax.get_xlabel() == "time (s)"
    assert motion.get_ylabel() == "displacement, gap (m)"
    assert _zero_height(ax) == pytest.approx(_zero_height(motion), abs=1e-9)
    assert 0.0 < _zero_height(ax) < 1.0
    assert _legend_hides_nothing(ax) == 4                # force, y1, y2, gap
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["force (N)", "y1 (m)", "y2 (m)", "gap (m)"]
    plt.close(ax.figure)


def test_damper_plot_with_a_lasting_contact_force_on_a_level_twin():
    primary = SpringMass(1.0, 4 * np.pi**2 * 100.0, damping_ratio=0.02)       # 10 Hz
    damper = ImpactDamper(primary, damper_mass=0.05, clearance=2e-3,
                          contact=LinearSpring(stiffness=2e5, damping=5.0),
                          excitation=HarmonicForce(2.0, 10.0))
    res = damper.simulate(n_cycles=30)
    assert np.any(res.force != 0)
    ax = res.plot(last_cycles=5)
    force = [a for a in ax.figure.axes if a is not ax][0]
    assert force.get_ylabel() == "contact force (N)" and ax.get_ylabel() == "displacement (mm)"
    assert _zero_height(ax) == pytest.approx(_zero_height(force), abs=1e-9)
    assert _legend_hides_nothing(ax) >= 3
    assert "contact force on the primary" in [t.get_text() for t in ax.get_legend().get_texts()]
    plt.close(ax.figure)
    # no empty plot from a count that is not one (it drew empty curves)
    for bad, kind in [(-3, ValueError), (0, ValueError), (2.5, TypeError)]:
        with pytest.raises(kind, match="last_cycles must be"):
            res.plot(last_cycles=bad)


def test_damper_plot_of_instantaneous_impacts_has_no_force_axis():
    primary = SpringMass(1.0, 4 * np.pi**2 * 100.0, damping_ratio=0.02)
    damper = ImpactDamper(primary, damper_mass=0.05, clearance=5e-3,
                          contact=InstantaneousImpact(0.6), excitation=HarmonicForce(1.0, 10.0))
    ax = damper.simulate(n_cycles=30).plot()
    assert len(ax.figure.axes) == 1
    assert _legend_hides_nothing(ax) >= 2
    plt.close(ax.figure)


def test_points_plot_legend_clear_of_every_point():
    from modalid import MultiOutputModalModel

    model = MultiOutputModalModel(
        poles=np.array([-0.3 + 40j, -0.5 + 110j]),
        residues=np.array([[-0.05j, -0.03j], [0.001 - 0.02j, 0.04j], [-0.05j, -0.03j]]),
        inverse_mass=[0.5, -0.2, 0.5], flexibility=[2e-4, 0.0, 2e-4],
        outputs=["drv", "b", "copy"], driving_point=0)
    res = solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(model), t_end=0.05,
                       dt=1e-4, method="laplace")
    ax = res.points[1].plot(quantity="velocity")
    assert ax.get_ylabel() == "velocity (m/s)" and ax.get_xlabel() == "time (s)"
    assert _legend_hides_nothing(ax) == 3
    plt.close(ax.figure)
