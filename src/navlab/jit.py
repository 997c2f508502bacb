"""numba's ``njit`` for navlab's kernels, with caches that go stale when any navlab module they use changes.

numba keys a cached function on its own source file only (``_CacheLocator.get_source_stamp``: a hash
of that file). But a compiled function holds the code of the navlab functions it calls, compiled in:
after ``git pull`` in an editable install changed ``sampling/reeds_shepp_length.py`` alone, Hybrid A*'s
cached search (``grid/hybrid_search.py``, unchanged) went on running the old Reeds–Shepp code, silently,
until its cache was deleted by hand. (A pip install rewrites every file, so every stamp changed anyway.)

:class:`DependencyStampLocator`, put first among numba's locators when this module is imported (every
navlab module compiling a function imports ``njit`` from here), keeps numba's cache folder and file
names for navlab's functions and extends the stamp with a hash of every navlab module the function's
module uses, directly or through others (:func:`dependency_hashes`): a change in any of them makes the
cache stale and numba compiles again. Other packages' functions get numba's own locators.

The dependencies are read when numba first compares or saves the stamp (the function's first call),
not when the function is decorated: by then every module it names is imported in full.

References
----------
numba 0.68, ``numba/core/caching.py`` (``_CacheLocator``, ``CacheImpl._locator_classes``,
``IndexDataCacheFile._load_index``: the stamp saved in the index is compared with ``!=``).
"""

from __future__ import annotations

import functools
import os
import sys
import types
from typing import Tuple

from numba import njit  # noqa: F401 (re-exported: navlab's modules import it from here)
from numba.core import caching

#: the package whose functions get the dependency stamp
PACKAGE = "navlab"


def _navlab_module_of(value) -> str:
    """The navlab module ``value`` is, or is defined in ("" for anything else)."""
    if isinstance(value, types.ModuleType):
        name = value.__name__
    else:
        name = getattr(value, "__module__", None)
        if not isinstance(name, str):  # a numba dispatcher's module is its Python function's
            name = getattr(getattr(value, "py_func", None), "__module__", "")
    return name if isinstance(name, str) and (name == PACKAGE or name.startswith(PACKAGE + ".")) else ""


def _uses(module_name: str) -> Tuple[str, ...]:
    """The navlab modules ``module_name``'s globals name (modules, or functions and objects defined in one)."""
    module = sys.modules.get(module_name)
    if module is None:
        return ()
    if getattr(getattr(module, "__spec__", None), "_initializing", False):
        return _read_uses(module)  # (a kernel called while its module still imports: not final, not kept)
    return _kept_uses(module_name)


@functools.lru_cache(maxsize=None)
def _kept_uses(module_name: str) -> Tuple[str, ...]:
    """:func:`_uses` of a module imported in full, read once per process."""
    return _read_uses(sys.modules[module_name])


def _read_uses(module: types.ModuleType) -> Tuple[str, ...]:
    names = {_navlab_module_of(value) for value in list(vars(module).values())}
    return tuple(sorted(names - {"", module.__name__}))


def dependency_hashes(module_name: str) -> Tuple[Tuple[str, bytes], ...]:
    """(module, hash of its source file) for every navlab module ``module_name`` uses, directly or through
    others, itself excluded (numba hashes its own file): sorted by name. The hashes are numba's own
    (``_hash_source_file``: the file's SHA-256, kept per mtime and size)."""
    seen, todo = set(), [module_name]
    while todo:
        for name in _uses(todo.pop()):
            if name not in seen:
                seen.add(name)
                todo.append(name)
    out = []
    for name in sorted(seen - {module_name}):
        path = getattr(sys.modules.get(name), "__file__", None)
        if path and os.path.isfile(path):
            st = os.stat(path)
            out.append((name, caching._hash_source_file(path, st.st_mtime, st.st_size)))
    return tuple(out)


class _Stamp:
    """numba's own stamp and the dependencies' hashes, read when first compared or saved (see the module)."""

    def __init__(self, own, module_name: str) -> None:
        self._own = own
        self._module_name = module_name
        self._value = None

    def value(self):
        if self._value is None:
            self._value = (self._own, dependency_hashes(self._module_name))
        return self._value

    def __eq__(self, other):
        return self.value() == (other.value() if isinstance(other, _Stamp) else other)

    def __ne__(self, other):
        return not self == other

    __hash__ = None

    def __reduce__(self):  # saved in the index as the plain tuple the next process compares with
        return tuple, (self.value(),)


class DependencyStampLocator(caching._CacheLocator):
    """numba's locator for a navlab function (the first of numba's own that takes it), its stamp extended
    with the hashes of the navlab modules the function's module uses (:func:`dependency_hashes`)."""

    def __init__(self, inner, module_name: str) -> None:
        self._inner = inner
        self._module_name = module_name

    def ensure_cache_path(self):
        return self._inner.ensure_cache_path()

    def get_cache_path(self):
        return self._inner.get_cache_path()

    def get_source_stamp(self):
        return _Stamp(self._inner.get_source_stamp(), self._module_name)

    def get_disambiguator(self):
        return self._inner.get_disambiguator()

    @classmethod
    def from_function(cls, py_func, py_file):
        module_name = getattr(py_func, "__module__", None) or ""
        if not (module_name == PACKAGE or module_name.startswith(PACKAGE + ".")):
            return None
        for locator in caching.CacheImpl._locator_classes:
            if locator is not cls:
                inner = locator.from_function(py_func, py_file)
                if inner is not None:
                    return cls(inner, module_name)
        return None


def _install() -> None:
    """Put :class:`DependencyStampLocator` first among numba's locators (once)."""
    classes = caching.CacheImpl._locator_classes
    if DependencyStampLocator not in classes:
        classes.insert(0, DependencyStampLocator)


_install()
