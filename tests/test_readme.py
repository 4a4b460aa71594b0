"""The README's Python examples run as written, and say what they print."""

import re
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")

README = Path(__file__).resolve().parents[1] / "README.md"
BLOCKS = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)


def test_readme_has_examples():
    assert len(BLOCKS) >= 2


@pytest.mark.filterwarnings("ignore:Hf_coh_chan_2 of .* lies outside:UserWarning")
@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_readme_example_runs(index, tmp_path, monkeypatch):
    repo = README.parent
    code = BLOCKS[index].replace('"tests/data/', f'"{repo}/tests/data/')
    monkeypatch.chdir(tmp_path)
    namespace = {}
    exec(compile(code, f"README.md example {index + 1}", "exec"), namespace)  # noqa: S102
    if "res" in namespace:  # the impact example: its comments state these numbers
        res = namespace["res"]
        assert res.method == "convolution" and res.dt == pytest.approx(1e-3)
        assert res.restitution == pytest.approx(0.69888, abs=1e-5)
        assert len(res.contact_intervals) == 2
