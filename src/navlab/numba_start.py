"""Cut numba's start-up in a process: SciPy's BLAS module without ``scipy.linalg``, no garbage collections
while numba builds its registries, numba imported without the modules a planning command does not use.

When a process loads its first compiled function (from numba's cache or not),
numba sets up its target and imports its array implementations
(``numba.np.arraymath``), which check at import that a BLAS is available:
``numba.np.linalg.ensure_blas`` runs ``import scipy.linalg.cython_blas``.
Importing that submodule first imports its package, ``scipy.linalg``, and
with it ``scipy._lib._array_api``, the array-API compatibility layer and
``numpy.f2py``: about a quarter of a second of CPU in a process that only
wanted one extension module's function pointers.

:func:`preload_cython_blas` loads that one extension module from its file and
registers it under its full name in ``sys.modules``, where numba's import
finds it; numba's BLAS check still runs (``_HAVE_BLAS`` stays True) and
``np.dot`` / ``np.linalg`` in compiled code still reach SciPy's BLAS and
LAPACK. A later ``import scipy.linalg`` works as usual (the package's own
``__init__`` does not import ``cython_blas``). A module imported before its
package is not an attribute of it, so ``scipy.linalg.cython_blas`` would stay
unset; :class:`_LinkToPackage`, a one-shot import hook, sets it as soon as
``scipy.linalg`` is imported, so every spelling of the import gives the module.

:func:`collections_paused` pauses Python's cyclic garbage collector for a
block: a process that loaded one compiled function holds about 110 000
objects the collector tracks (19 000 after ``import numpy``), nearly all
long-lived (numba's typing and lowering registries), and the collections
that their creation triggers walk them several times over for nothing. The
``navlab plan`` command runs its one query inside it: 1.05 -> 0.95 s of CPU
(medians of 10 interleaved runs, load 7). Pausing only while kernels load
and collecting after gains nothing: the first collection then walks all of
them at once.

:func:`import_numba_lean` imports numba without PyYAML and with
``importlib.metadata`` deferred; ``navlab.numba_cached_loads`` loads cached
kernels without numba's registries.

References
----------
numba 0.68, ``numba/np/arraymath.py`` (``_HAVE_BLAS = _check_blas()``) and
``numba/np/linalg.py`` (``ensure_blas``); Python's import system,
https://docs.python.org/3/reference/import.html#the-module-cache (a module
found in ``sys.modules`` is returned as is, its parents are not imported);
Python's ``gc`` module, https://docs.python.org/3/library/gc.html (collections
are triggered by allocations; a generation's survivors are walked again in
the next).
"""

from __future__ import annotations

import contextlib
import gc
import importlib
import importlib.machinery
import importlib.util
import os
import sys

BLAS_MODULE = "scipy.linalg.cython_blas"


def preload_cython_blas() -> bool:
    """Load ``scipy.linalg.cython_blas`` on its own, before numba's first kernel asks for it.

    Returns
    -------
    bool
        True when the module is in ``sys.modules`` afterwards (loaded now or
        before). False, silently, when there is nothing to gain or nothing to
        load: ``scipy.linalg`` already imported (the normal import is then
        cheap), numba's array implementations already loaded, no SciPy, or
        no such file; numba then imports as it always does.
    """
    if BLAS_MODULE in sys.modules:
        return True
    if "scipy.linalg" in sys.modules or "numba.np.arraymath" in sys.modules:
        return False  # nothing to save: let the ordinary import run
    spec = _extension_spec()
    if spec is None:
        return False
    module = importlib.util.module_from_spec(spec)
    sys.modules[BLAS_MODULE] = module
    try:
        spec.loader.exec_module(module)
    except Exception:  # a SciPy this does not fit: undo, and let numba import it its way
        sys.modules.pop(BLAS_MODULE, None)
        return False
    sys.meta_path.insert(0, _LinkToPackage())
    return True


class _LinkToPackage:
    """Set ``scipy.linalg.cython_blas`` when ``scipy.linalg`` is imported after the preload.

    Python sets a submodule as an attribute of its package when it imports the
    submodule; the preload imported it before the package existed, so the
    package would lack it (``import scipy.linalg.cython_blas;
    scipy.linalg.cython_blas`` raised AttributeError in a user's code). This
    finder answers only for ``scipy.linalg``, once: it takes the ordinary spec
    from the other finders and links the module after the package's code ran.
    A meta path finder needs only ``find_spec``
    (https://docs.python.org/3/reference/import.html#the-meta-path), so the
    class skips ``importlib.abc.MetaPathFinder`` and the 10 ms its import costs.
    """

    def find_spec(self, name, path=None, target=None):
        if name != "scipy.linalg":
            return None
        sys.meta_path.remove(self)  # one-shot; and the search below must not find this finder again
        spec = importlib.util.find_spec(name)
        if spec is None or spec.loader is None or not hasattr(spec.loader, "exec_module"):
            return spec
        run_package = spec.loader.exec_module

        def exec_module(package):
            run_package(package)
            package.cython_blas = sys.modules.get(BLAS_MODULE)

        spec.loader.exec_module = exec_module  # this spec's own loader object
        return spec


def _extension_spec():
    """The spec of cython_blas's extension file, found without importing ``scipy``
    (``find_spec`` of a top-level package reads no code) or ``scipy.linalg``."""
    try:
        scipy_spec = importlib.util.find_spec("scipy")
    except (ImportError, ValueError):
        return None
    if scipy_spec is None or not scipy_spec.submodule_search_locations:
        return None
    folder = os.path.join(list(scipy_spec.submodule_search_locations)[0], "linalg")
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:  # this interpreter's ABI tags, in its order
        path = os.path.join(folder, "cython_blas" + suffix)
        if os.path.isfile(path):
            return importlib.util.spec_from_file_location(BLAS_MODULE, path)
    return None


NUMBA_CONFIG_FILE = ".numba_config.yaml"  # numba.core.config reads it from the working folder, if present


def import_numba_lean() -> None:
    """Import numba without the two modules it imports for files and plug-ins a planning command lacks.

    ``import numba`` imports PyYAML (``numba.core.config``, to read a
    ``.numba_config.yaml`` in the working folder, which it opens only if the
    file exists) and ``importlib.metadata`` (``numba.core.entrypoints``, to
    find third-party extensions, read at the first compile: see
    ``numba_cached_loads.cached_loads_without_registries``): 25-30 ms and 20-50 ms of a
    ``navlab plan`` that needs neither.

    - ``importlib.metadata`` is put in ``sys.modules`` through Python's
      ``importlib.util.LazyLoader``: its code runs at its first attribute
      access, so numba's ``from importlib import metadata`` costs nothing and
      a later use loads it as usual.
    - PyYAML cannot be deferred that way (an ``import yaml`` statement reads
      the module's ``__spec__``, which runs a lazy module), so when the
      working folder has no ``.numba_config.yaml`` numba's configuration is
      imported with ``sys.modules["yaml"] = None`` (Python's way to make an
      import fail): numba records that it has no YAML, which it consults only
      for that file. The entry is removed at once; navlab's own YAML loading
      imports PyYAML as usual.

    Does nothing when numba is imported already.

    References
    ----------
    Python documentation: ``importlib.util.LazyLoader`` and "Implementing lazy
    imports", https://docs.python.org/3/library/importlib.html#implementing-lazy-imports;
    "The module cache" (a ``None`` entry raises ``ModuleNotFoundError``),
    https://docs.python.org/3/reference/import.html#the-module-cache;
    numba 0.68, ``numba/core/config.py`` (``_HAVE_YAML``, ``_config_fname``).
    """
    if "numba" in sys.modules:
        return
    _import_lazily("importlib.metadata")
    hide_yaml = "yaml" not in sys.modules and not os.path.isfile(NUMBA_CONFIG_FILE)
    if hide_yaml:
        sys.modules["yaml"] = None
    try:
        import numba  # noqa: F401 - the import is the point
    finally:
        if hide_yaml and sys.modules.get("yaml", 0) is None:
            del sys.modules["yaml"]


def _import_lazily(name: str) -> None:
    """Put module ``name`` in ``sys.modules`` with its code deferred to its first attribute access.

    A module already imported, or not found, is left alone.
    """
    if name in sys.modules:
        return
    try:
        spec = importlib.util.find_spec(name)
    except (ImportError, ValueError):
        return
    if spec is None or spec.loader is None or not hasattr(spec.loader, "exec_module"):
        return
    spec.loader = importlib.util.LazyLoader(spec.loader)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    parent, _, child = name.rpartition(".")
    if parent:
        setattr(sys.modules[parent], child, module)  # as the import system links a submodule to its package


@contextlib.contextmanager
def collections_paused():
    """Pause the cyclic garbage collector for the block; restore it after.

    For work that makes long-lived objects, not garbage (loading numba and
    kernels, one query in a process of its own): reference counting still
    frees whatever dies meanwhile; only reference cycles wait for the next
    collection after the block. A collector that was off stays off.
    """
    was_on = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_on:
            gc.enable()
