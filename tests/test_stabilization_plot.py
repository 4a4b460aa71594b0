"""modalid.stabilization.plot_stabilization: a chart that stays readable on noisy data
(stable, frequency-stable and new poles told apart, the new ones faded, the selected poles
marked, the measured FRF on a twin axis in its quantity, the legend off the data)."""

from __future__ import annotations

import functools
import warnings

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from modalid import FRFSet  # noqa: E402
from modalid.stabilization import plot_stabilization, stabilization_table  # noqa: E402


@functools.cache
def _noisy_fit():
    """A free rod's accelerance, 15 modes in 0.05-8 Hz, 5 % noise and a 1 % floor."""
    from data_synth import Rod, lightly_damped, synthetic_frf
    from modalid import ModalFit

    truth = lightly_damped(Rod(1.0, 1.0, support="free"), 30, 0.01)
    data = synthetic_frf(truth, np.linspace(0.05, 8.0, 1600), quantity="accelerance",
                         noise=0.05, noise_floor=0.01, seed=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit().fit(data)
    return fit, data


def _lines(ax):
    return {line.get_label(): line for line in ax.get_lines()}


def _table(freq_hz, orders=12):
    """A table whose poles at ``freq_hz`` (2 % damping) repeat at every order."""
    freq_hz = np.asarray(freq_hz, float)
    wn = 2 * np.pi * freq_hz
    poles = -0.02 * wn + 1j * wn * np.sqrt(1 - 0.02**2)
    return stabilization_table([poles] * orders, (0.5 * freq_hz.min(), 2 * freq_hz.max()))


def test_noisy_chart_tells_the_poles_apart_and_marks_the_selected():
    fit, data = _noisy_fit()
    table = fit.stabilization_
    assert (~table["stable_freq"]).sum() > 100            # noisy: many wandering poles
    fig, ax = plt.subplots()
    assert plot_stabilization(table, frf=data, selected=fit.poles_, ax=ax) is ax
    lines = _lines(ax)
    stable = lines["stable frequency and damping"]
    freq_only = lines["stable frequency"]
    new = lines["new (not stable)"]
    faint = lines["stable, no selected pole"]
    # every pole drawn once; the strong markers near a selected pole, the rest faint
    assert len(stable.get_xdata()) > 0
    assert (len(stable.get_xdata()) + len(freq_only.get_xdata()) + len(faint.get_xdata())
            == table["stable_freq"].sum())
    assert len(new.get_xdata()) == (~table["stable_freq"]).sum()
    f_sel = np.abs(fit.poles_) / (2 * np.pi)
    strong = np.concatenate([stable.get_xdata(), freq_only.get_xdata()])
    assert np.all(np.min(np.abs(strong[:, None] - f_sel) / f_sel, axis=1) <= 0.01)
    assert faint.get_alpha() < freq_only.get_alpha() and faint.get_zorder() < stable.get_zorder()
    # filled circles, open circles, small faded dots
    assert stable.get_marker() == "o" and stable.get_markerfacecolor() != "none"
    assert freq_only.get_marker() == "o" and freq_only.get_markerfacecolor() == "none"
    assert new.get_markersize() < stable.get_markersize()
    assert new.get_alpha() < 1.0 and new.get_zorder() < stable.get_zorder()
    selected = lines[f"selected ({len(fit.poles_)})"]
    assert len(selected.get_xdata()) == len(fit.poles_)
    np.testing.assert_allclose(np.sort(selected.get_xdata()),
                               np.sort(np.abs(fit.poles_)) / (2 * np.pi))
    # the measured FRF, in its quantity and units, on a twin behind the poles
    twin = [a for a in fig.axes if a is not ax][0]
    assert twin.get_ylabel() == "|accelerance| (m/s²/N)" and twin.get_yscale() == "log"
    assert ax.get_zorder() > twin.get_zorder()
    assert ax.get_xscale() == "linear"                    # evenly spread modes
    # the legend lies above the data area, over none of the poles
    fig.canvas.draw()
    legend = ax.get_legend().get_window_extent()
    assert legend.y0 >= ax.get_window_extent().y1
    assert {t.get_text() for t in ax.get_legend().get_texts()} >= {
        "stable frequency and damping", "stable frequency", "new (not stable)",
        f"selected ({len(fit.poles_)})", "|accelerance| (measured)"}
    plt.close(fig)


def test_a_cleared_chart_fades_the_stable_poles_no_selected_pole_stands_on():
    """Stable columns at 100 and 300 Hz (2 % damping) and at 100.5 Hz (20 %): with the
    100 Hz pole selected, its column keeps the strong marker; the 300 Hz column (no
    selected pole) and the 100.5 Hz one (ten times the damping) are faint. On a 0.1 Hz
    grid (eight lines: 0.8 Hz) a column 0.5 Hz away still counts, on a 0.01 Hz grid
    (0.08 Hz) it does not."""
    wn = 2 * np.pi * np.array([100.0, 100.5, 300.0])
    zeta = np.array([0.02, 0.2, 0.02])
    poles = -zeta * wn + 1j * wn * np.sqrt(1 - zeta**2)
    table = stabilization_table([poles] * 10, (50.0, 600.0))
    selected = poles[:1]
    ax = plot_stabilization(table, selected=selected)
    lines = _lines(ax)
    np.testing.assert_allclose(lines["stable frequency and damping"].get_xdata(), 100.0)
    np.testing.assert_allclose(np.unique(lines["stable, no selected pole"].get_xdata()),
                               [100.5, 300.0])
    plt.close(ax.figure)
    near = -0.02 * 2 * np.pi * 100.4 + 2j * np.pi * 100.4 * np.sqrt(1 - 0.02**2)
    table = stabilization_table([np.append(poles, near)] * 10, (50.0, 600.0))
    for step, strong in ((0.1, [100.0, 100.4]), (0.01, [100.0])):
        grid = FRFSet(np.arange(50.0, 600.0, step), np.ones((1, int(round(550 / step))),
                                                             complex), quantity="receptance")
        ax = plot_stabilization(table, selected=selected, frf=grid)
        drawn = _lines(ax)["stable frequency and damping"].get_xdata()
        np.testing.assert_allclose(np.unique(drawn), strong)
        plt.close(ax.figure)


def test_a_new_figure_without_frf_or_selection():
    fit, _ = _noisy_fit()
    ax = plot_stabilization(fit.stabilization_)
    assert ax.get_xlabel() == "frequency (Hz)" and ax.get_ylabel() == "model order"
    assert len(ax.figure.axes) == 1 and not any(
        label.startswith("selected") for label in _lines(ax))
    plt.close(ax.figure)


def test_frequency_axis_log_for_poles_crowded_low_linear_for_spread_ones():
    wide = _table(np.geomspace(1.0, 1000.0, 12))
    ax = plot_stabilization(wide)
    assert ax.get_xscale() == "log"
    plt.close(ax.figure)
    even = _table(np.linspace(100.0, 1000.0, 10))
    ax = plot_stabilization(even)
    assert ax.get_xscale() == "linear"
    plt.close(ax.figure)
    ax = plot_stabilization(even, xscale="log")
    assert ax.get_xscale() == "log"
    plt.close(ax.figure)
    with pytest.raises(ValueError, match="xscale must be 'auto', 'linear' or 'log', got 'lin'"):
        plot_stabilization(even, xscale="lin")


def test_an_frf_set_draws_its_mean_magnitude():
    freq = np.linspace(50.0, 1500.0, 300)
    values = np.vstack([1.0 / (1.0 + (freq / 400.0) ** 2), 2.0 / (1.0 + (freq / 700.0) ** 2)])
    frfs = FRFSet(freq, values.astype(complex), quantity="mobility")
    ax = plot_stabilization(_table(np.linspace(100.0, 1000.0, 10)), frf=frfs)
    twin = ax.figure.axes[1]
    assert twin.get_ylabel() == "mean |mobility| (m/s/N)"
    np.testing.assert_allclose(twin.get_lines()[0].get_ydata(), np.abs(values).mean(axis=0))
    plt.close(ax.figure)
