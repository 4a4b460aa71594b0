"""The documentation site: every public name has an API page, and the site builds with
warnings as errors (gallery executed, API pages generated), so it cannot rot."""

import importlib
import os
import pkgutil
import re
import subprocess
import sys
from pathlib import Path

import pytest
from public_api import docs_conf

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
PACKAGES = ("modalid", "impactpred", "data_synth")
#: internal layers, not API (docs/architecture.md describes them)
INTERNAL = ("impactpred.engine", "impactpred.solvers")


def _public_modules():
    for package in PACKAGES:
        yield package
        for info in pkgutil.walk_packages(importlib.import_module(package).__path__,
                                          package + "."):
            parts = info.name.split(".")
            if any(p.startswith("_") for p in parts) or info.name.startswith(INTERNAL):
                continue
            yield info.name


def test_every_public_name_is_on_an_api_page():
    documented = {id(getattr(importlib.import_module(module), name))
                  for module, names in docs_conf().public_names() for name in names}
    missing = [f"{module}.{name}" for module in _public_modules()
               for name in getattr(importlib.import_module(module), "__all__", [])
               if id(getattr(importlib.import_module(module), name)) not in documented]
    assert not missing, f"public names without an API page (docs/conf.py API_MODULES): {missing}"


def test_pages_in_the_toctree_exist_and_every_page_is_in_one():
    index = (DOCS / "index.md").read_text()
    pages = {p.stem for p in DOCS.glob("*.md")} - {"index"}
    listed = {line.strip() for line in index.splitlines()
              if line.strip() and line.strip() in pages | {"api"}}
    assert pages == listed, f"pages not in the toctree: {sorted(pages - listed)}"


@pytest.mark.slow
def test_site_builds_without_warnings(tmp_path):
    env = dict(os.environ, OMP_NUM_THREADS="1", MPLBACKEND="Agg")
    build = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q",
                            "-b", "html", "-d", str(tmp_path / "doctrees"), str(DOCS),
                            str(tmp_path / "html")],
                           capture_output=True, text=True, env=env, timeout=900)
    assert build.returncode == 0, build.stderr[-5000:]
    html = tmp_path / "html"
    for module, names in docs_conf().public_names():
        for name in names:
            assert (html / "api" / "generated" / f"{module}.{name}.html").is_file(), name
    # every example and figure drew its own image
    for page, n_figures in (("gallery", 4), ("method", 3)):
        images = set(re.findall(r'<img[^>]*src="(_images/[^"]+)"',
                                (html / f"{page}.html").read_text()))
        assert len(images) >= n_figures, (page, images)
    performance = (html / "performance.html").read_text()
    # the tables come from benchmarks/README.md at build time
    assert "bench_solvers.py" in performance and performance.count("<table") >= 5
