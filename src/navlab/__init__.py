"""navlab: 2D mobile-robot path planning and navigation.

The public names below are imported on first use (PEP 562), so ``import
navlab`` and the ``navlab`` command start fast: numba, scipy and the planners
load only when something needs them.
"""

import importlib

__version__ = "0.1.0"

#: public name -> the module (relative to navlab) that defines it
_LAZY = {
    "plan": "planning", "planner_names": "planning", "Result": "result", "Status": "result", "Tree": "result",
    "make_planner": "sampling", "make_sampler": "sampling", "World": "world", "load_world": "world",
    "load_source": "world.sources",
}

__all__ = sorted(_LAZY) + ["__version__"]


def __getattr__(name):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'navlab' has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value  # once loaded, a plain attribute
    return value


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
