"""The public API as the documentation lists it, for the tests that walk it (numpydoc
sections, option defaults, API pages): ``docs/conf.py``'s ``public_names()`` and the
public methods the classes define."""

import importlib
import importlib.util
import inspect
from pathlib import Path

DOCS = Path(__file__).resolve().parents[1] / "docs"


def docs_conf():
    """``docs/conf.py`` loaded as a module (the single list of public names)."""
    spec = importlib.util.spec_from_file_location("_docs_conf", DOCS / "conf.py")
    conf = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(conf)
    return conf


def public_objects():
    """``(qualified name, object)`` of every public name of the API pages."""
    for module_name, names in docs_conf().public_names():
        module = importlib.import_module(module_name)
        for name in names:
            yield f"{module_name}.{name}", getattr(module, name)


def public_methods(cls):
    """``(name, member)`` of the public functions, class methods and static methods that
    ``cls`` itself defines (``member`` as stored in the class: a ``classmethod`` or
    ``staticmethod`` object for those)."""
    for attr, member in vars(cls).items():
        if not attr.startswith("_") and (inspect.isfunction(member) or isinstance(
                member, (classmethod, staticmethod))):
            yield attr, member
