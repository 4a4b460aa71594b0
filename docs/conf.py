"""Sphinx configuration of the impactpred documentation site.

Build: ``.venv/bin/python -m sphinx -W -b html docs docs/_build/html`` (``pip install
-e ".[docs]"``). The API pages (``docs/api/``) are written by this file from the public
modules' ``__all__`` at every build, so every public name has a page; the gallery scripts
(``docs/gallery/*.py``) run at build time through matplotlib's plot directive.
"""

import importlib
import os
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))        # the packages of this checkout, installed or not

import impactpred  # noqa: E402

project = "impactpred"
author = "impactpred developers"
copyright = "2026, impactpred developers"   # noqa: A001 - Sphinx's name
release = impactpred.__version__
version = release

extensions = [
    "myst_parser",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "matplotlib.sphinxext.plot_directive",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build"]
templates_path = ["_templates"]
myst_enable_extensions = ["dollarmath"]
myst_heading_anchors = 3
suppress_warnings = ["myst.header"]   # included files (benchmarks/README.md) start at level 1

html_theme = "alabaster"
html_theme_options = {"description": "impact prediction from measured dynamics",
                      "fixed_sidebar": True}
html_static_path = []

autosummary_generate = True
autosummary_imported_members = True
autodoc_default_options = {"members": True, "inherited-members": False}
autodoc_inherit_docstrings = False   # not the standard library's or scikit-learn's
autodoc_typehints = "none"           # numpydoc's Parameters sections carry the types
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False

plot_include_source = True
plot_html_show_source_link = False
plot_html_show_formats = False
plot_formats = [("png", 80)]
plot_rcparams = {"figure.figsize": (7.0, 3.6), "figure.dpi": 80}
plot_basedir = str(DOCS / "gallery")
plot_working_directory = str(DOCS / "gallery")

# ---------------------------------------------------------------- the API pages
#: public modules and what their page is called; a name is documented once, on the first
#: module (in this order) whose ``__all__`` lists it. ``impactpred.engine`` and
#: ``impactpred.solvers`` are internal layers (see architecture.md), not API.
API_MODULES = [
    "modalid", "modalid.io", "modalid.model", "modalid.hammer", "modalid.stabilization",
    "modalid.receptance", "modalid.statespace", "modalid.validation", "modalid.cli",
    "impactpred", "impactpred.damper", "impactpred.damper.result", "impactpred.predict",
    "impactpred.truncation", "impactpred.uncertainty", "impactpred.paper",
    "impactpred.benchmark", "impactpred.api", "impactpred.body", "impactpred.points",
    "impactpred.parallel", "impactpred.cli",
    "data_synth", "data_synth.reference_impacts", "data_synth.measure",
]


def public_names():
    """``[(module name, [public names documented there])]`` over :data:`API_MODULES`."""
    seen, pages = set(), []
    for name in API_MODULES:
        try:
            module = importlib.import_module(name)
        except ModuleNotFoundError:
            continue                       # an optional module not in this checkout
        new = []
        for n in getattr(module, "__all__", []):
            if id(getattr(module, n)) not in seen:
                seen.add(id(getattr(module, n)))
                new.append(n)
        if new:
            pages.append((name, new))
    return pages


def _write_api_pages(app):
    out = DOCS / "api"
    out.mkdir(exist_ok=True)
    pages = public_names()
    for old in out.glob("*.rst"):
        if old.stem not in {module for module, _ in pages}:
            old.unlink()
    for module, names in pages:
        title = f"``{module}``"
        lines = [title, "=" * len(title), ""]
        parent, _, last = module.rpartition(".")
        if parent and getattr(importlib.import_module(parent), last) is not \
                importlib.import_module(module):   # impactpred.predict: a function too
            lines += [importlib.import_module(module).__doc__.split("\n\n")[0].strip()]
        else:
            lines += [f".. automodule:: {module}", "   :no-members:"]
        lines += ["", f".. currentmodule:: {module}", "", ".. autosummary::",
                 "   :toctree: generated", "   :nosignatures:", ""]
        lines += [f"   {n}" for n in names]
        page, text = out / f"{module}.rst", "\n".join(lines) + "\n"
        if not page.exists() or page.read_text() != text:   # unchanged: not read again
            page.write_text(text)


def _skip_member(app, what, name, obj, skip, options):
    """Leave out what a class inherits from scikit-learn (``set_*_request`` and the like)."""
    module = getattr(obj, "__module__", None) or ""
    return True if module.startswith("sklearn") or name.endswith("_request") else None


def setup(app):
    app.connect("autodoc-skip-member", _skip_member)
    _write_api_pages(app)       # before autosummary reads the sources
    os.environ.setdefault("MPLBACKEND", "Agg")
