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
