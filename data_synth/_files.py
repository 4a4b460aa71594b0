"""Where the measured example files are: :func:`example_data_path`."""

from __future__ import annotations

from os import PathLike
from pathlib import Path

__all__ = ["example_data_path"]

#: the folder of the measured example files, relative to the source tree's root
_DATA = Path("tests") / "data"


def example_data_path(name: str) -> Path:
    """Absolute path of a measured example file (``tests/data/<name>``), from any directory.

    The files (``case1.mat``, ``case2.mat``, ``meas_point_1.txt`` ... ``_3.txt``; licences in
    ``tests/data/README.md``) belong to the source tree, not to an installed wheel. They are
    looked for in the source tree this package was imported from (an editable install or a
    checkout on ``sys.path``), then in the current directory and each of its parents.

    Parameters
    ----------
    name : str
        File name inside ``tests/data``, e.g. ``"case1.mat"``.

    Returns
    -------
    pathlib.Path
        The absolute path of the file.

    Raises
    ------
    FileNotFoundError
        Naming every place looked at, when none holds the file.
    """
    if not isinstance(name, (str, PathLike)):
        raise TypeError(f"name must be a file name (str), got {type(name).__name__}")
    name = str(name)
    relative = Path(name)
    if relative.is_absolute() or ".." in relative.parts:
        raise ValueError(f"name must be a file name inside {_DATA}, got {name!r}")
    here = Path.cwd().resolve()
    roots = [Path(__file__).resolve().parents[1], here, *here.parents]
    tried = []
    for root in roots:
        path = root / _DATA / relative
        if path.is_file():
            return path
        tried.append(str(path.parent))
    raise FileNotFoundError(f"no example file {name!r}: looked in {', '.join(tried)}; the "
                            "files come with the source repository (tests/data), not with an "
                            "installed wheel")
