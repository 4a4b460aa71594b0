"""The distribution: a wheel built from the sources installs in a fresh virtual
environment and its command line runs; one version for the three packages."""

import ast
import os
import re
import shutil
import subprocess
import sys
import sysconfig
import tomllib
import venv
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("modalid", "impactpred", "data_synth")


def test_one_version_for_the_three_packages():
    import data_synth
    import impactpred
    import modalid

    stated = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    assert modalid.__version__ == impactpred.__version__ == data_synth.__version__ == stated
    changelog = (ROOT / "CHANGELOG.md").read_text()
    assert f"## {stated}" in changelog or "## Unreleased" in changelog


def _requirement_names(requirements):
    return {re.split(r"[<>=!~\[ ;]", r)[0].lower().replace("-", "_") for r in requirements}


def test_every_imported_third_party_module_is_declared():
    """A module the packages import at the top of a module is a dependency (threadpoolctl
    once was not); one imported inside a function or a ``try`` may be an extra's."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    required = _requirement_names(project["dependencies"])
    optional = required | _requirement_names(
        r for extra in project.get("optional-dependencies", {}).values() for r in extra)
    distribution = {"sklearn": "scikit_learn"}            # import name -> distribution
    local = set(PACKAGES) | set(sys.stdlib_module_names) | {"__future__"}
    missing = set()
    for package in PACKAGES:
        for path in (ROOT / package).rglob("*.py"):
            tree = ast.parse(path.read_text())
            top = {id(node) for node in tree.body}
            for node in ast.walk(tree):
                if isinstance(node, ast.Import):
                    names = [alias.name for alias in node.names]
                elif isinstance(node, ast.ImportFrom) and not node.level:
                    names = [node.module]
                else:
                    continue
                for name in names:
                    root = name.split(".")[0]
                    if root in local:
                        continue
                    wanted = distribution.get(root, root).lower()
                    if wanted not in (required if id(node) in top else optional):
                        missing.add(f"{root} ({path.relative_to(ROOT)})")
    assert not missing, f"imported but not declared in pyproject.toml: {sorted(missing)}"


def test_every_dependency_has_its_reason_in_the_readme():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    readme = (ROOT / "README.md").read_text()
    section = readme[readme.index("## Dependencies"):].lower()
    names = {re.split(r"[<>=!~\[ ;]", r)[0] for r in project["dependencies"]}
    names |= {re.split(r"[<>=!~\[ ;]", r)[0] for extra in
              project.get("optional-dependencies", {}).values() for r in extra}
    names.discard(project["name"])
    aliases = {"control": "python-control", "scikit-learn": "scikit-learn"}
    unexplained = sorted(n for n in names if aliases.get(n.lower(), n).lower() not in section
                         and n.lower() not in section)
    assert not unexplained, f"dependencies without a reason in README.md: {unexplained}"


@pytest.mark.slow
def test_wheel_installs_and_runs_in_a_fresh_environment(tmp_path):
    # build from a copy of the sources, so that the build leaves nothing in the checkout
    src = tmp_path / "src"
    src.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(ROOT / name, src / name)
    for package in PACKAGES:
        shutil.copytree(ROOT / package, src / package,
                        ignore=shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc"))
    wheels = tmp_path / "wheels"
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w",
                    str(wheels), str(src)], check=True, timeout=600)
    (wheel,) = wheels.glob("impactpred-*.whl")

    # a fresh environment; its dependencies are this environment's (no download), the
    # packages themselves only from the wheel
    env_dir = tmp_path / "venv"
    venv.create(env_dir, with_pip=False)
    bin_dir = env_dir / ("Scripts" if os.name == "nt" else "bin")
    python = bin_dir / "python"
    fresh_site = subprocess.run([python, "-c", "import sysconfig; print(sysconfig.get_path("
                                 "'purelib'))"], capture_output=True, text=True,
                                check=True).stdout.strip()
    deps = [sysconfig.get_path("purelib"), sysconfig.get_path("platlib")]
    Path(fresh_site, "_deps_of_the_test_environment.pth").write_text("\n".join(deps) + "\n")
    subprocess.run([sys.executable, "-m", "pip", "--python", str(python), "install", "-q",
                    "--no-deps", "--no-index", str(wheel)], check=True, timeout=300)

    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH",)}
    env["OMP_NUM_THREADS"] = "1"
    where = subprocess.run(
        [python, "-c", "import impactpred, modalid, data_synth, pathlib; "
         "print(*(pathlib.Path(m.__file__).parent for m in (impactpred, modalid, data_synth)),"
         " impactpred.__version__)"],
        capture_output=True, text=True, check=True, env=env, cwd=tmp_path).stdout.split()
    for location in where[:3]:
        assert Path(location).is_relative_to(env_dir), f"imported from {location}, not the wheel"
        assert (Path(location) / "py.typed").is_file()
    assert where[3] == tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]

    helped = subprocess.run([bin_dir / "impactpred", "paper", "--help"], capture_output=True,
                            text=True, env=env, cwd=tmp_path, timeout=120)
    assert helped.returncode == 0, helped.stderr
    assert "--out" in helped.stdout
    # a tiny job: the paper's case (a), two equal free rods (the closed form)
    job = subprocess.run(
        [python, "-c", "from data_synth import Rod; from impactpred import Body, solve_impact; "
         "r = solve_impact(Body(Rod(1.0, 1.0), velocity=1.0), Body(Rod(1.0, 1.0), "
         "velocity=-1.0), t_end=3.0); print(r.method, round(r.restitution, 9))"],
        capture_output=True, text=True, env=env, cwd=tmp_path, timeout=120)
    assert job.returncode == 0, job.stderr
    assert job.stdout.split() == ["closed_form", "1.0"]
