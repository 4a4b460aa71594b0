"""The Python examples of the README and of the docs' pages run as written, and say what
they print."""

import re
from pathlib import Path

import matplotlib
import numpy as np
import pytest

from modalid import mac

matplotlib.use("Agg")

README = Path(__file__).resolve().parents[1] / "README.md"
PAGES = [README, *sorted((README.parent / "docs").glob("*.md"))]
BLOCKS = [block for page in PAGES
          for block in re.findall(r"```python\n(.*?)```", page.read_text(), flags=re.S)]


def test_readme_has_examples():
    assert len(BLOCKS) >= 2


@pytest.mark.filterwarnings("ignore:Hf_coh_chan_2 of .* lies outside:UserWarning")
@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_readme_example_runs(index, tmp_path, monkeypatch):
    code = BLOCKS[index]
    monkeypatch.chdir(tmp_path)       # as written, from a directory that is not the repository's
    namespace = {}
    exec(compile(code, f"README.md example {index + 1}", "exec"), namespace)  # noqa: S102
    if "0.69888" in code:  # the impact example: its comments state these numbers
        res = namespace["res"]
        assert res.method == "convolution" and res.dt == pytest.approx(1e-3)
        assert res.restitution == pytest.approx(0.69888, abs=1e-5)
        assert len(res.contact_intervals) == 2
    if "mac(" in code:  # the multi-point example: common poles, shapes, point responses
        model, beam, xi = namespace["model"], namespace["beam"], namespace["xi"]
        assert model.n_outputs == 3 and model.outputs[model.driving_point] == "xi=0"
        shapes = mac(model.mode_shapes(scaling="mass"), beam.mode_shapes(xi, 8))
        assert np.all(shapes.diagonal() > 0.99)
        peaks = namespace["res"].points[1].peaks()["peak_displacement"].to_numpy()
        assert peaks[0] > peaks[1] > peaks[2] > 0   # the tip moves most, the root least
        # the numbers in the comments; nothing moves before the force acts (t = 0)
        points, exact = namespace["res"].points[1], namespace["exact"].points[1]
        velocity = points.peaks()["peak_velocity"].to_numpy()
        np.testing.assert_allclose(velocity, [1.389, 0.469, 0.422], atol=2e-3)
        np.testing.assert_allclose(exact.peaks()["peak_velocity"], [1.64, 0.46, 0.438],
                                   atol=2e-3)
        # away from the tip the fit is within 5 % of the model its FRFs came from (the tip's
        # peak, 0.5 ms after contact, lives far above the band)
        np.testing.assert_allclose(velocity[1:], exact.peaks()["peak_velocity"][1:], rtol=0.05)
        assert np.max(np.abs(points.displacement[:, 0])) < 1e-12 * np.max(peaks)
        force = namespace["res"].force                      # no jump at contact (was 837 N)
        assert abs(force[0]) < 1e-9 * np.max(force)
        assert np.all(np.abs(points.velocity[1:, 0]) < 0.2)   # static correction: 0.17, 0.08
    if "example_data_path(" in code:  # the measured file is found from any directory
        assert Path(namespace["path"]) == README.parent / "tests" / "data" / "case1.mat"
    if "est.frf, weights=weights" in code:  # the hammer recipe: the truth, window undone
        modes, truth = namespace["modes"], namespace["truth"].modes
        assert len(modes) == 3
        np.testing.assert_allclose(modes["frequency_hz"], truth["frequency_hz"], rtol=1e-4)
        np.testing.assert_allclose(modes["damping_ratio"], truth["damping_ratio"], rtol=0.05)
    if 'predict("mass:0.5", "rod.csv"' in code:  # a measured FRF file to the impact
        pred = namespace["pred"]
        assert pred.fits[1].report_["verdict"] == "ok"
        assert pred.figures["restitution"] == pytest.approx(0.4513, abs=5e-4)
        # the comment's comparison: the same impact on the damped rod the file came from
        from data_synth import LumpedMass
        from impactpred import Body, Rigid, solve_impact
        exact = solve_impact(Body(LumpedMass(0.5), velocity=1.0), Body(namespace["truth"]),
                             gap=0.0, contact=Rigid(), t_end=4.0).restitution
        assert exact == pytest.approx(0.4509, abs=1e-4)
        assert pred.figures["restitution"] == pytest.approx(exact, abs=1e-3)
    if "masri_caughey(" in code:  # the impact damper reaches the classical closed form
        res, exact = namespace["res"], namespace["exact"]
        assert exact.exists and exact.stable and res.impacts_per_cycle == 2.0
        assert res.primary_amplitude == pytest.approx(exact.amplitude, rel=1e-4)
