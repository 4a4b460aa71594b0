"""The command line: help, the exact models, the paper's cases."""

import pandas as pd
import pytest

from impactpred.cli import main
from impactpred.paper import run_paper_cases


def test_help_lists_the_commands(capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["--help"])
    assert exit_info.value.code == 0
    out = capsys.readouterr().out
    assert "paper" in out and "models" in out


def test_models_command_prints_exact_frequencies(tmp_path, capsys):
    assert main(["models", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "0.2500" in out and "0.7500" in out          # fixed rod: (k - 1/2)/(2T) Hz
    assert "0.5596" in out                               # cantilever: eps_1^2/(2 pi T)
    assert (tmp_path / "exact_models_frf.png").stat().st_size > 1000


def test_paper_command_writes_figures_and_table(tmp_path, capsys):
    assert main(["paper", "--out", str(tmp_path)]) == 0
    table = pd.read_csv(tmp_path / "paper_cases.csv", index_col="case")
    assert table.loc["a", "restitution"] == pytest.approx(1.0, abs=1e-12)
    assert table.loc["a", "contact_duration_s"] == pytest.approx(2.0, abs=1e-12)
    assert table.loc["b_equal_material", "contact_duration_s"] == pytest.approx(1.5, abs=1e-9)
    assert table.loc["c", "restitution"] == pytest.approx(0.69888, abs=2e-4)
    assert table.loc["d", "n_contacts"] == 1
    for key in ("a", "b_equal_mass", "b_equal_material", "c", "d"):
        assert (tmp_path / f"fig4_{key}.png").stat().st_size > 1000


def test_paper_table_without_files():
    table = run_paper_cases(None, plot=False)
    assert 0 < table.loc["b_equal_mass", "restitution"] < 1
    assert (table.loc["b_equal_mass", "peak_force_N"]
            > table.loc["b_equal_material", "peak_force_N"])


def test_cli_reports_bad_input_without_a_traceback(capsys):
    assert main(["paper", "--dt", "-1", "--no-plot"]) == 2
    assert "dt must be positive" in capsys.readouterr().err


def test_benchmark_command_quick_writes_tables(tmp_path, capsys):
    assert main(["benchmark", "--quick", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "mass-rod M/m=1" in out and "no prediction with e > 1" in out
    table = pd.read_csv(tmp_path / "synthetic_benchmark.csv")
    assert len(table) == 2 and (tmp_path / "synthetic_benchmark.md").exists()
