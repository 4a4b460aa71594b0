"""The habits of a maintained library, checked: ruff (configured in pyproject.toml), mypy
on the packages, numpydoc sections on every public function, class and method, and the
docstrings' examples run as doctests."""

import ast
import doctest
import importlib
import inspect
import os
import pkgutil
import subprocess
import sys
import textwrap
from pathlib import Path

import matplotlib
import pytest
from numpydoc.docscrape import ClassDoc, FunctionDoc
from public_api import public_methods, public_objects

matplotlib.use("Agg")

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("modalid", "impactpred", "data_synth")


def test_ruff_passes():
    run = subprocess.run([sys.executable, "-m", "ruff", "check", "--no-cache",
                          "--output-format", "concise", "."],
                         cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout[-5000:] + run.stderr[-2000:]


@pytest.mark.slow
def test_mypy_passes(tmp_path):
    run = subprocess.run([sys.executable, "-m", "mypy", "--cache-dir", str(tmp_path)],
                         cwd=ROOT, capture_output=True, text=True, timeout=900,
                         env=dict(os.environ, OMP_NUM_THREADS="1"))
    assert run.returncode == 0, run.stdout[-5000:] + run.stderr[-2000:]


# ---------------------------------------------------------------- numpydoc sections
def _api():
    """``(qualified name, object)`` of every public function, class and public method: the
    API pages' names (docs/conf.py) and the methods their classes define."""
    for qualified, obj in public_objects():
        if inspect.isfunction(obj):
            yield qualified, obj
        elif inspect.isclass(obj):
            yield qualified, obj
            for attr, member in public_methods(obj):
                yield f"{qualified}.{attr}", getattr(member, "__func__", member)


def _returns_a_value(function) -> bool:
    try:
        tree = ast.parse(textwrap.dedent(inspect.getsource(function)))
    except (OSError, TypeError, SyntaxError):
        return False
    top = tree.body[0]
    todo = list(ast.iter_child_nodes(top))
    while todo:                                  # not into nested functions or lambdas
        node = todo.pop()
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda,
                             ast.ClassDef)):
            continue
        if isinstance(node, (ast.Yield, ast.YieldFrom)):
            return True
        if isinstance(node, ast.Return) and node.value is not None and not (
                isinstance(node.value, ast.Constant) and node.value.value is None):
            return True
        todo.extend(ast.iter_child_nodes(node))
    return False


def _missing_sections(obj) -> list:
    is_class = inspect.isclass(obj)
    doc = ClassDoc(obj, config={"show_class_members": False}) if is_class else FunctionDoc(obj)
    try:
        target = obj.__init__ if is_class else obj
        parameters = [p for p in inspect.signature(target).parameters
                      if p not in ("self", "cls", "args", "kwargs")]
    except (TypeError, ValueError):
        parameters = []
    if is_class and (issubclass(obj, Exception) or obj.__init__ is object.__init__):
        parameters = []
    missing = [] if doc["Summary"] else ["Summary"]
    if parameters and not (doc["Parameters"] or doc["Other Parameters"]
                           or (is_class and doc["Attributes"])):
        missing.append("Parameters")
    if not is_class and _returns_a_value(obj) and not (doc["Returns"] or doc["Yields"]):
        missing.append("Returns")
    return missing


#: names still without their sections; the list may only shrink (the test fails when a
#: name on it is complete, so that it is taken off)
INCOMPLETE: set[str] = set()   # public names whose sections are still to write


def test_every_public_function_has_its_numpydoc_sections():
    found = {name: _missing_sections(obj) for name, obj in _api()}
    assert len(found) > 150                      # the walk reached the API
    missing = {name: m for name, m in found.items() if m and name not in INCOMPLETE}
    assert not missing, "numpydoc sections missing:\n" + "\n".join(
        f"  {name}: {', '.join(m)}" for name, m in sorted(missing.items()))
    done = sorted(name for name in INCOMPLETE if name in found and not found[name])
    assert not done, f"complete now, take them off INCOMPLETE: {done}"


# ---------------------------------------------------------------- doctests
def _modules():
    for package in PACKAGES:
        yield package
        path = importlib.import_module(package).__path__
        for info in pkgutil.walk_packages(path, package + "."):
            yield info.name


def test_docstring_examples_run_as_doctests(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    examples = 0
    for name in _modules():
        module = importlib.import_module(name)
        for test in finder.find(module, name):
            if test.examples:
                examples += len(test.examples)
                runner.run(test)
    results = runner.summarize(verbose=False)
    assert examples >= 10 and results.attempted >= 10
    assert results.failed == 0, f"{results.failed} of {results.attempted} doctest examples failed"


def _imports(root: Path, top: str) -> dict:
    """``{module: modules of the tree it imports}`` for the ``.py`` files under
    ``root/top`` (``top`` "" for the files of ``root`` itself, as ``benchmarks/`` runs
    them), every import statement counted, those inside functions too."""
    modules = {}
    for path in sorted((root / top).rglob("*.py")):
        parts = path.relative_to(root).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        modules[name] = path
    graph = {}
    for name, path in modules.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        targets = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                if node.level:
                    parts = package.split(".")
                    base = parts[:len(parts) - node.level + 1]
                    module = ".".join(base + ([node.module] if node.module else []))
                else:
                    module = node.module or ""
                targets |= {module} | {f"{module}.{a.name}" for a in node.names}
            elif isinstance(node, ast.Import):
                targets |= {a.name for a in node.names}
        graph[name] = {t for t in targets if t in modules and t != name}
    return graph


def _cycle(graph: dict):
    """One import cycle of ``graph`` (a list of modules), or None."""
    state = {}

    def visit(node, trail):
        state[node] = "open"
        for nxt in sorted(graph[node]):
            if state.get(nxt) == "open":
                return trail[trail.index(nxt):] + [nxt]
            if nxt not in state:
                found = visit(nxt, trail + [nxt])
                if found:
                    return found
        state[node] = "done"
        return None

    for start in sorted(graph):
        if start not in state:
            found = visit(start, [start])
            if found:
                return found
    return None


@pytest.mark.parametrize("root, top", [(ROOT, p) for p in PACKAGES]
                         + [(ROOT / "benchmarks", "")])
def test_no_import_circles(root, top):
    """One direction of dependence inside every package and among the benchmark scripts
    (issue #17): an import circle, even through a deferred import, ties two modules into
    one. The check itself finds a circle where there is one."""
    assert _cycle(_imports(root, top)) is None, _cycle(_imports(root, top))
    assert _cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": set()}) == ["a", "b", "c", "a"]


#: the longest a module may grow (the guide's "small modules with one job each", issue #17)
MAX_MODULE_LINES = 600


@pytest.mark.parametrize("package", PACKAGES)
def test_no_module_is_over_the_line_limit(package):
    """Every module of the packages has at most :data:`MAX_MODULE_LINES` lines: a module
    that outgrows it holds more than one job (uncertainty.py had reached 656 lines)."""
    lengths = {path.relative_to(ROOT).as_posix(): len(path.read_text().splitlines())
               for path in (ROOT / package).rglob("*.py")}
    assert lengths, f"no module found under {package}"
    too_long = {name: n for name, n in lengths.items() if n > MAX_MODULE_LINES}
    assert not too_long, too_long
