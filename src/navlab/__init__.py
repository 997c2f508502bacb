"""navlab: 2D mobile-robot path planning and navigation.

The public names below are imported on first use (PEP 562), so ``import
navlab`` and the ``navlab`` command start fast: numba, scipy and the planners
load only when something needs them.
"""

import importlib

__version__ = "0.1.0"


def lazy_attributes(package: str, table: dict):
    """A package's ``__getattr__`` and ``__dir__`` that import each public name on first use (PEP 562).

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    table : dict
        Public name -> the submodule (relative to ``package``) that defines it.

    Returns
    -------
    (callable, callable)
        ``__getattr__`` (imports the submodule, caches the value as a plain
        attribute, ``AttributeError`` for any other name) and ``__dir__`` (the
        public names and the dunders).

    References
    ----------
    PEP 562, "Module __getattr__ and __dir__", https://peps.python.org/pep-0562/
    """
    namespace = importlib.import_module(package).__dict__

    def __getattr__(name):
        module = table.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(f".{module}", package), name)
        namespace[name] = value  # once loaded, a plain attribute
        return value

    def __dir__():  # the public names, subpackages and dunders, not the module's helpers (importlib, ...)
        own = {n for n, v in namespace.items() if n.startswith("__") or getattr(v, "__name__", "") == f"{package}.{n}"}
        return sorted(set(table) | set(namespace.get("__all__", ())) | own)

    return __getattr__, __dir__


#: public name -> the module (relative to navlab) that defines it
_LAZY = {
    "plan": "planning", "planner_names": "planning", "Result": "result", "Status": "result", "Tree": "result",
    "make_planner": "sampling", "make_sampler": "sampling", "World": "world", "load_world": "world",
    "load_source": "world.sources", "NavlabError": "errors", "ParameterError": "errors",
}

__all__ = sorted(_LAZY) + ["__version__"]
__getattr__, __dir__ = lazy_attributes(__name__, _LAZY)
