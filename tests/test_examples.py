"""Every notebook in ``examples/`` runs top to bottom, in a kernel of this very interpreter.

The notebooks are found by globbing, so a notebook added later is executed too. Each one
must be saved with its outputs cleared (the repository holds sources, not results) and
must run without an error in any cell. Notebooks that state conclusions are also checked
for them (see ``EXPECTED_OUTPUT``).

The kernel: ``nbclient`` starts the kernel named ``python3`` through jupyter_client's
kernel-spec search path. A ``python3`` spec installed by a user or a system (for instance
pointing at another Python without this project) could win that search, so the test
writes its own ``python3`` spec, running ``sys.executable -m ipykernel_launcher``, into a
temporary directory that it puts first on ``JUPYTER_PATH``. Nothing has to be installed
with ``ipykernel install``; ``ipykernel`` (the ``test`` extra) must be importable here.
"""

from __future__ import annotations

import json
import re
import sys
import time
from pathlib import Path

import nbformat
import pytest
from jupyter_client.kernelspec import KernelSpecManager
from nbclient import NotebookClient

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
NOTEBOOKS = sorted(EXAMPLES.glob("*.ipynb"))

#: seconds allowed per cell (a generous bound: CI machines may be loaded)
CELL_TIMEOUT = 600

#: text that a notebook's executed outputs must contain (regular expressions)
EXPECTED_OUTPUT = {
    "restitution_is_not_a_constant.ipynb": [
        r"\*\*Conclusions: the coefficient of restitution is not a material constant\.\*\*",
        r"e after all contacts ranges over",
        r"matches\s+Saint-Venant's exact solution to \d",
        r"Notebook run time: \d+\.\d s",
    ],
    "impact_damper_design.ipynb": [
        r"\*\*Conclusions: impact damper on the identified primary\.\*\*",
        # 2000 cycles: every run steady (at 250, four drifted and it said 1.67 %)
        r"matches Masri &\s+Caughey's closed form at \d+ operating points to 0\.0\d % in "
        r"amplitude",
        r"\*\*What the finite contact does\.\*\*",
        r"\*Optimum clearance\.\* At resonance",
        r"Notebook run time: \d+\.\d s",
    ],
    "measured_beam_damper.ipynb": [
        r"\*\*Conclusions: an impact damper for the first bending mode of the measured beam\.\*\*",
        r"signs of the modal masses, mode by mode: \+ - \+ - \+ -",
        r"is the fitted model passive \(a valid driving point\)\? False",
        r"\*Best design on the grid:\* mass ratio",
        r"Notebook run time: \d+\.\d s",
    ],
}
#: at least this many figures (PNG outputs)
EXPECTED_FIGURES = {"restitution_is_not_a_constant.ipynb": 4, "impact_damper_design.ipynb": 5,
                    "measured_beam_damper.ipynb": 4}


def test_examples_exist():
    assert NOTEBOOKS, f"no notebooks found in {EXAMPLES}"


def test_example_data_is_found_from_any_directory(tmp_path, monkeypatch):
    from data_synth import example_data_path

    monkeypatch.chdir(tmp_path)
    data = EXAMPLES.parent / "tests" / "data"
    for name in ("case1.mat", "meas_point_1.txt"):
        assert example_data_path(name) == data / name
    with pytest.raises(FileNotFoundError, match="no example file 'missing.txt'"):
        example_data_path("missing.txt")
    with pytest.raises(ValueError):
        example_data_path("../README.md")
    with pytest.raises(TypeError, match="name must be a file name \\(str\\), got NoneType"):
        example_data_path(None)        # it looked for a file named "None"
    # no notebook opens a file by a path relative to the working directory
    for path in NOTEBOOKS:
        code = "\n".join("".join(cell.source) for cell in nbformat.read(path, as_version=4).cells
                         if cell.cell_type == "code")
        relative = r"""["']\.\.?/|Path\(["']\.\.?["']\)|["']tests/data"""
        assert not re.search(relative, code), path.name


@pytest.fixture
def this_python_kernel(tmp_path, monkeypatch):
    """Make kernel name ``python3`` resolve to ``sys.executable``; return the name."""
    spec_dir = tmp_path / "jupyter" / "kernels" / "python3"
    spec_dir.mkdir(parents=True)
    spec = {"argv": [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
            "display_name": "Python 3 (this interpreter)", "language": "python",
            "env": {"OPENBLAS_NUM_THREADS": "1", "MPLBACKEND": "Agg"}}
    (spec_dir / "kernel.json").write_text(json.dumps(spec))
    monkeypatch.setenv("JUPYTER_PATH", str(tmp_path / "jupyter"))
    found = KernelSpecManager().get_kernel_spec("python3")
    assert found.argv[0] == sys.executable, found.argv
    return "python3"


def _outputs(nb):
    for index, cell in enumerate(nb.cells):
        if cell.cell_type == "code":
            for output in cell.get("outputs", []):
                yield index, output


def _text(output) -> str:
    if output.output_type == "stream":
        return output.text
    if output.output_type == "error":
        return "\n".join(output.traceback)
    data = output.get("data", {})
    return "\n".join(data.get(kind, "") for kind in ("text/markdown", "text/plain", "text/html"))


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.name for p in NOTEBOOKS])
def test_notebook_saved_without_outputs(path):
    nb = nbformat.read(path, as_version=4)
    nbformat.validate(nb)
    dirty = [i for i, cell in enumerate(nb.cells) if cell.cell_type == "code"
             and (cell.get("outputs") or cell.get("execution_count") is not None)]
    assert not dirty, f"{path.name}: clear the outputs of cells {dirty} before saving"


@pytest.mark.slow
@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.name for p in NOTEBOOKS])
def test_notebook_executes(path, this_python_kernel, tmp_path):
    nb = nbformat.read(path, as_version=4)
    # run from an empty directory: a notebook must find its data from anywhere
    workdir = tmp_path / "cwd"
    workdir.mkdir()
    client = NotebookClient(nb, timeout=CELL_TIMEOUT, kernel_name=this_python_kernel,
                            allow_errors=False,
                            resources={"metadata": {"path": str(workdir)}})
    start = time.perf_counter()
    client.execute()  # raises CellExecutionError, naming the cell, on the first error
    elapsed = time.perf_counter() - start
    print(f"{path.name}: executed in {elapsed:.1f} s")

    code_cells = [cell for cell in nb.cells if cell.cell_type == "code"]
    assert code_cells, f"{path.name} has no code cell"
    assert all(cell.execution_count is not None for cell in code_cells)
    errors = [i for i, output in _outputs(nb) if output.output_type == "error"
              or (output.output_type == "stream" and "Traceback (most recent call last)"
                  in output.text)]
    assert not errors, f"{path.name}: errors in cells {errors}"

    text = "\n".join(_text(output) for _, output in _outputs(nb))
    for pattern in EXPECTED_OUTPUT.get(path.name, []):
        assert re.search(pattern, text), f"{path.name}: no output matches {pattern!r}"
    figures = sum("image/png" in output.get("data", {}) for _, output in _outputs(nb))
    assert figures >= EXPECTED_FIGURES.get(path.name, 0), f"{path.name}: {figures} figures"
    # numbers in the conclusions are formatted from variables: none is left unformatted
    assert not re.search(r"\{[A-Za-z_][^{}]*\}", "\n".join(
        output["data"]["text/markdown"] for _, output in _outputs(nb)
        if "text/markdown" in output.get("data", {}))), "unformatted placeholder in the text"
