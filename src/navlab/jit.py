"""numba's ``njit`` for navlab's kernels, with caches that go stale when navlab code they compile in changes.

numba keys a cached function on its own source file only (``_CacheLocator.get_source_stamp``). But a
compiled function holds the code of the navlab functions it calls, and the navlab constants it reads,
compiled in: after ``git pull`` in an editable install changed ``sampling/reeds_shepp_length.py`` alone,
Hybrid A*'s cached search (``grid/hybrid_search.py``, unchanged) went on running the old Reeds–Shepp
code, silently, until its cache was deleted by hand. (A pip install rewrites every file, so every stamp
changed anyway.)

:class:`DependencyStampLocator`, put first among numba's locators when this module is imported (every
navlab module compiling a function imports ``njit`` from here; a test keeps it so), keeps numba's cache
folder and file names for navlab's functions and extends numba's stamp with the hashes of the navlab
files whose code or constants the function's compiled code can reach (:func:`compiled_in`): the
functions it calls, theirs in turn, the intrinsics and the constants they read. A change in one of those
files makes the cache stale and numba compiles again; a change elsewhere (a message in ``limits.py``,
which Python code around the kernels uses) leaves it as it is. Other packages' functions get numba's own
locators, and so does everything when this numba lacks the pieces the locator builds on
(:func:`install`).

The reach is read when numba first compares or saves the stamp (the function's first call), not when
the function is decorated: by then every module it names is imported in full.

References
----------
numba 0.59–0.68, ``numba/core/caching.py`` (``_CacheLocator``, ``CacheImpl._locator_classes``,
``IndexDataCacheFile._load_index``: the stamp saved in the index is compared with ``!=``).
"""

from __future__ import annotations

import ast
import functools
import hashlib
import importlib.util
import os
import sys
import types
from typing import Any, Dict, Iterator, Optional, Set, Tuple

from numba import njit  # noqa: F401 (re-exported: navlab's modules import it from here)
from numba.core import caching
from numba.core.dispatcher import Dispatcher
from numba.core.extending import _Intrinsic

#: the package whose functions get the dependency stamp
PACKAGE = "navlab"


def _is_navlab(module_name: Any) -> bool:
    return isinstance(module_name, str) and (module_name == PACKAGE or module_name.startswith(PACKAGE + "."))


@functools.lru_cache(maxsize=None)
def _file_hash(path: str, mtime: float, size: int) -> bytes:
    """The SHA-256 of a source file, kept per path, mtime and size (a file changed while the process
    runs is read again)."""
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).digest()


def _code_names(code: types.CodeType) -> Iterator[str]:
    """The global and attribute names ``code`` reads, its nested functions' too."""
    yield from code.co_names
    for const in code.co_consts:
        if isinstance(const, types.CodeType):
            yield from _code_names(const)


@functools.lru_cache(maxsize=None)
def _imported_names(module_name: str) -> Dict[str, str]:
    """``{name: module}`` for the module's top-level ``from navlab... import name`` statements (relative
    ones resolved): where a constant it reads by name comes from, numba having frozen its value into the
    machine code. Read from the file's import lines before its first definition, not its whole syntax tree."""
    module = sys.modules.get(module_name)
    path = getattr(module, "__file__", None)
    if not path or not os.path.isfile(path):
        return {}
    with open(path, encoding="utf-8") as f:
        lines = f.read().splitlines()
    statements, i = [], 0
    # the statements at column 0 starting "from", with their parenthesised continuations, up to the first
    # definition (navlab imports at the top of a module)
    while i < len(lines) and not lines[i].startswith(("def ", "class ", "@")):
        if lines[i].startswith("from "):
            text = lines[i]
            while text.count("(") > text.count(")") and i + 1 < len(lines):
                i += 1
                text += "\n" + lines[i]
            statements.append(text)
        i += 1
    out: Dict[str, str] = {}
    package = module_name if path.endswith("__init__.py") else module_name.rpartition(".")[0]
    for text in statements:
        try:
            node = ast.parse(text).body[0]
        except (SyntaxError, IndexError):  # a docstring's line that starts with "from"
            continue
        if isinstance(node, ast.ImportFrom):
            source = importlib.util.resolve_name("." * node.level + (node.module or ""), package)
            if _is_navlab(source):
                out.update({alias.asname or alias.name: source for alias in node.names})
    return out


def compiled_in(py_func) -> Tuple[str, ...]:
    """The navlab modules, ``py_func``'s own excepted, whose code or constants its compiled code can hold.

    Walks what numba compiles in: every global and attribute name the function's code reads, resolved in
    its globals (and its closure's cells), and its default values: a navlab dispatcher is followed into its
    own function, an intrinsic or a class (an ``IntEnum``'s members) counts its module, a navlab module
    object counts itself and is followed into the names the code reads from it, and any other value (a
    number, a tuple, an array) counts the module the name was imported from into the module it was read
    in (:func:`_imported_names`). Python-only helpers around the kernels (messages, checks) are not reached.
    Not seen: a constant computed at import from another module's (``B = other.A * 2``): it counts its own
    module only.

    Parameters
    ----------
    py_func : function
        A dispatcher's Python function.

    Returns
    -------
    tuple of str
        Module names, sorted.
    """
    own = py_func.__module__
    modules: Set[str] = set()
    seen: Set[int] = set()
    todo = [py_func]
    while todo:
        func = todo.pop()
        if id(func) in seen:
            continue
        seen.add(id(func))
        names = set(_code_names(func.__code__))
        scope, home = func.__globals__, func.__module__
        cells = [cell.cell_contents for cell in (func.__closure__ or ()) if _filled(cell)]
        # (name, value, the module the name is read in)
        values = [(name, scope[name], home) for name in names if name in scope] + [("", v, home) for v in cells]
        values += [(name, scope[name], home) for name in _default_names(func)]
        looked: Set[Tuple[str, int]] = set()
        while values:
            name, value, where = values.pop()
            if (name, id(value)) in looked:
                continue
            looked.add((name, id(value)))
            if isinstance(value, types.ModuleType):
                if _is_navlab(value.__name__):
                    modules.add(value.__name__)
                    values += [(attr, getattr(value, attr), value.__name__) for attr in names
                               if hasattr(value, attr)]
            elif isinstance(value, Dispatcher):
                if _is_navlab(value.py_func.__module__):
                    modules.add(value.py_func.__module__)
                    todo.append(value.py_func)
            elif isinstance(value, _Intrinsic):
                modules.add(getattr(value._defn, "__module__", ""))
            elif isinstance(value, type):
                modules.add(getattr(value, "__module__", ""))
            elif name and not callable(value):
                modules.add(_imported_names(where).get(name, ""))
    return tuple(sorted(name for name in modules if _is_navlab(name) and name != own))


def _default_names(func) -> Iterator[str]:
    """The global names of ``func``'s module that hold one of its default values (``def f(x, s=SCALE)``: the
    value is frozen in the machine code, and only its name says where it came from)."""
    defaults = list(func.__defaults__ or ()) + list((func.__kwdefaults__ or {}).values())
    if not defaults:
        return
    for name, value in func.__globals__.items():
        if any(value is d for d in defaults) and not callable(value) and not isinstance(value, types.ModuleType):
            yield name


def _filled(cell) -> bool:
    try:
        cell.cell_contents
    except ValueError:  # (a closure variable not assigned yet)
        return False
    return True


def dependency_hashes(py_func) -> Tuple[Tuple[str, bytes], ...]:
    """(module, hash of its source file) for each of :func:`compiled_in`'s modules."""
    out = []
    for name in compiled_in(py_func):
        path = getattr(sys.modules.get(name), "__file__", None)
        if path and os.path.isfile(path):
            st = os.stat(path)
            out.append((name, _file_hash(path, st.st_mtime, st.st_size)))
    return tuple(out)


class _Stamp:
    """numba's own stamp and :func:`dependency_hashes`, read when first compared or saved (see the module):
    saved as the plain tuple a later process compares its own with."""

    def __init__(self, own, py_func) -> None:
        self._own = own
        self._py_func = py_func
        self._value: Optional[tuple] = None

    def value(self) -> tuple:
        """(numba's stamp, the dependencies' hashes), computed once."""
        if self._value is None:
            self._value = (self._own, dependency_hashes(self._py_func))
        return self._value

    def __eq__(self, other):
        return self.value() == (other.value() if isinstance(other, _Stamp) else other)

    def __ne__(self, other):
        return not self == other

    __hash__ = None

    def __reduce__(self):
        return tuple, (self.value(),)


class DependencyStampLocator(caching._CacheLocator):
    """numba's locator for a navlab function (the first of numba's own that takes it), its stamp extended
    with :func:`dependency_hashes`.

    Parameters
    ----------
    inner : numba locator
        The locator numba would have used: the cache's folder and names are its.
    py_func : function
        The function cached.
    """

    def __init__(self, inner, py_func) -> None:
        self._inner = inner
        self._py_func = py_func

    def __getattr__(self, name: str) -> Any:
        # What numba reads of a locator beyond the methods below (``_py_file``, for the warning that a
        # function cannot be cached: without it that warning was an AttributeError) is the inner one's.
        inner = self.__dict__.get("_inner")
        if name.startswith("__") or inner is None:  # (copy and pickle probe dunders before __init__)
            raise AttributeError(name)
        return getattr(inner, name)

    def ensure_cache_path(self):
        return self._inner.ensure_cache_path()

    def get_cache_path(self):
        return self._inner.get_cache_path()

    def get_source_stamp(self):
        return _Stamp(self._inner.get_source_stamp(), self._py_func)

    def get_disambiguator(self):
        return self._inner.get_disambiguator()

    @classmethod
    def from_function(cls, py_func, py_file):
        if not _is_navlab(getattr(py_func, "__module__", None)):
            return None
        for locator in caching.CacheImpl._locator_classes:
            if locator is not cls:
                inner = locator.from_function(py_func, py_file)
                if inner is not None:
                    return cls(inner, py_func)
        return None


def install() -> bool:
    """Put :class:`DependencyStampLocator` first among numba's locators (once); whether it is there.

    numba's locator list is private (``CacheImpl._locator_classes``, numba 0.59–0.68): a numba without
    it keeps its own locators, each navlab kernel keyed on its own file as numba keys any function."""
    classes = getattr(getattr(caching, "CacheImpl", None), "_locator_classes", None)
    if not isinstance(classes, list):
        return False
    if DependencyStampLocator not in classes:
        classes.insert(0, DependencyStampLocator)
    return True


install()
