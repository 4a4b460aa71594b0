"""The modalid command line: fit a measured FRF file, write the model and plots."""

from pathlib import Path

import pytest

from modalid import ModalModel
from modalid.cli import main

CASE1 = str(Path(__file__).parent / "data" / "case1.mat")


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_fit_command_prints_the_modes_and_writes_the_model(tmp_path, capsys):
    status = main(["fit", CASE1, "--quantity", "accelerance", "--fmin", "20",
                   "--fmax", "400", "--weighting", "noise", "--not-driving-point",
                   "--out", str(tmp_path)])
    assert status == 0
    out = capsys.readouterr().out
    assert "212.08" in out
    model = ModalModel.from_json(tmp_path / "case1_model.json")
    assert model.n_modes >= 4
    assert (tmp_path / "case1_fit.png").stat().st_size > 1000


def test_fit_command_reports_bad_input(capsys):
    assert main(["fit", CASE1]) == 2
    assert "quantity" in capsys.readouterr().err
    assert main(["fit", "no_such_file.csv", "--quantity", "receptance"]) == 2


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_fit_command_models_an_exponential_window(windowed_free_rod_csv, tmp_path, capsys):
    """A free rod's mobility from an exponentially windowed hammer test, as a CSV: with
    --window-decay and --record-length the model written has the rod's mass (1 kg)."""
    path, options = windowed_free_rod_csv
    masses = {}
    window = ["--window-decay", str(options["window_decay_rate"]),
              "--record-length", str(options["record_length"])]
    # plain: the whole band, a passive fit without the window's model
    plain = ["--fmin", "0", "--driving-point", "yes"]
    for label, extra in (("window", window), ("plain", plain)):
        out = tmp_path / label
        assert main(["fit", str(path), "--out", str(out)] + extra) == 0
        masses[label] = 1.0 / ModalModel.from_json(out / "free_rod_model.json").inverse_mass
    assert masses["window"] == pytest.approx(1.0, rel=3e-3)
    assert abs(masses["plain"] - 1.0) > 0.05       # the windowed mass line read as 1/(M s^2)
    out = tmp_path / "dense"
    assert main(["fit", str(path), "--missed-modes", "dense", "--out", str(out)] + window) == 0
    dense = ModalModel.from_json(out / "free_rod_model.json")
    assert 1.0 / dense.inverse_mass == pytest.approx(1.0, rel=3e-3)
    capsys.readouterr()
    assert main(["fit", str(path), "--window-decay", "-1"]) == 2
    assert "window_decay_rate" in capsys.readouterr().err
