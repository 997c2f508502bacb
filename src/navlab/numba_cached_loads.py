"""Load cached numba kernels in a process of navlab's own with only what the loaded machine code needs.

For the ``navlab plan`` and ``navlab grid plan`` commands on a warm cache,
where start-up is the point. numba's own first load of a cached function
prepares the process for compiling, which a cached function does not need:

- ``Cache.load_overload`` first calls ``target_context.refresh()``, which
  imports about 60 modules of typing and lowering implementations
  (``numba.np.arraymath``, ``numba.cpython.*``, ...) and installs their
  registries: 80-90 ms of a 0.2 s first load.
- Unpickling a cached library's environments imports the modules they name,
  numba's own ``numba.np.arrayobj`` in nearly every kernel (35-60 ms).
- Every dispatcher reads all installed distributions' entry points before its
  first call, for third-party extensions (7-14 ms, and ``importlib.metadata``).
- numba compiles its runtime's own LLVM module (NRT's atomic reference
  counts) from IR in every process: 30-40 ms.

:func:`cached_loads_without_registries` switches all four off for the rest of
the process. Whatever compiles later still gets everything: numba's compiler
refreshes both contexts itself before each compile (``CompilerBase.__init__``),
which installs every registry and runs the extensions' entry points; a cache
miss goes there.

References
----------
numba 0.68: ``numba/core/caching.py`` (``Cache.load_overload``,
``IndexDataCacheFile``), ``numba/core/base.py`` (``BaseContext.refresh``),
``numba/core/cpu.py`` (``load_additional_registries``),
``numba/core/compiler.py`` (``CompilerBase.__init__``),
``numba/core/environment.py`` (``_rebuild_env``), ``numba/core/dispatcher.py``
(``_compilation_chain_init_hook``), ``numba/core/runtime/nrt.py``
(``_Runtime.initialize``) and ``numba/core/runtime/nrtdynmod.py``
(``compile_nrt_functions``), ``numba/core/codegen.py``
(``serialize_using_object_code``, ``unserialize_library``, ``magic_tuple``).
"""

from __future__ import annotations

import hashlib
import os
import pickle
import sys
import tempfile


def cached_loads_without_registries() -> bool:
    """Let numba load cached functions without its registries, environments' modules, extensions or runtime compile.

    For a process of navlab's own (see the module's docstring): it changes
    numba for the rest of the process, not only for navlab's kernels. Call
    it once numba is imported; later calls do nothing.

    Returns
    -------
    bool
        True when cached loads skip the registries from now on; False,
        changing nothing, when this numba lacks the pieces the replacement
        calls (another numba version: its own loads run as they always do).
    """
    from numba.core import caching
    from numba.core.runtime import rtsys

    cache = caching.Cache
    if getattr(cache.load_overload, "skips_registries", False):
        return True
    if not all(hasattr(cache, name) for name in ("_load_overload", "_guard_against_spurious_io_errors")) or \
            not callable(getattr(rtsys, "initialize", None)):
        return False

    def load_overload(self, sig, target_context):
        rtsys.initialize(target_context)  # the runtime the machine code calls; refresh() would start with it too
        with self._guard_against_spurious_io_errors():
            return self._load_overload(sig, target_context)
        # None when the guard swallowed an I/O error, as numba's own method returns: the caller compiles

    load_overload.skips_registries = True
    load_overload.__doc__ = cache.load_overload.__doc__
    cache.load_overload = load_overload
    _environments_without_imports()
    _extensions_at_first_compile()
    _runtime_from_cache()
    return True


def _extensions_at_first_compile() -> None:
    """Let numba run its third-party extensions' entry points at a process's first compile, not at its first call.

    Before typing a call's arguments, every dispatcher runs
    ``entrypoints.init_all()``, which reads the entry points of every
    installed distribution (7-14 ms here, and ``importlib.metadata``'s
    import, 20-50 ms) to find ``numba_extensions``. navlab's kernels take
    only numpy arrays and scalars, so a process that loads them from the
    cache needs no extension; numba's compiler runs ``init_all()`` itself
    when it refreshes the target before any compile
    (``CPUContext.load_additional_registries``), so whatever compiles still
    sees every extension first.
    """
    from numba.core import dispatcher

    dispatcher_class = getattr(dispatcher, "Dispatcher", None)
    if dispatcher_class is not None and hasattr(dispatcher_class, "_compilation_chain_init_hook"):
        dispatcher_class._compilation_chain_init_hook = _no_extensions_yet  # noqa: SLF001


def _no_extensions_yet(dispatcher) -> None:
    """A dispatcher's pre-call hook that leaves the extensions to the first compile's refresh (see above)."""


def _environments_without_imports() -> None:
    """Rebuild a cached function's environments without importing numba's implementation modules for them.

    A cached library pickles an ``Environment`` for every function in it,
    numba's own helpers included (``numba.np.arrayobj``'s array constructors
    in nearly every kernel), and unpickling one imports the module it names
    to hold that module's globals: ``numba.np.arrayobj`` and what it imports
    (``numba.cpython.unicode``, ``charseq``, ``slicing``, the sorts) are about
    60 ms of a first load, for globals that nopython code never reads (only
    object-mode lowering reads ``env.globals``; nopython code reads
    ``env.consts``, which stay as pickled). For a numba module not yet
    imported, the environment gets a dict holding only the module's name,
    which is what pickling it again reads (``Environment.__reduce__``,
    ``can_cache``); every other environment is rebuilt by numba's own code.
    """
    from numba.core import environment

    rebuild = environment._rebuild_env  # noqa: SLF001 - numba's unpickling hook, looked up by name at load time
    if getattr(rebuild, "imports_nothing", False) or not hasattr(environment, "lookup_environment"):
        return

    def rebuild_env(modname, consts, env_name):
        if environment.lookup_environment(env_name) is not None or \
                not str(modname).startswith("numba.") or modname in sys.modules:
            return rebuild(modname, consts, env_name)
        env = environment.Environment({"__name__": modname})
        env.consts[:] = consts
        env.env_name = env_name
        environment.Environment._memo[env_name] = env  # noqa: SLF001 - as numba's own rebuild records it
        return env

    rebuild_env.imports_nothing = True
    environment._rebuild_env = rebuild_env  # noqa: SLF001


def _runtime_from_cache() -> None:
    """Load numba's runtime module (NRT's atomic reference counts) from a file instead of compiling it.

    ``rtsys.initialize`` builds that small LLVM module from IR and compiles it
    in every process that loads a kernel (30-40 ms, most of it LLVM's code
    generation). The replacement of ``nrtdynmod.compile_nrt_functions`` builds
    the IR as before and keys a file on it (its text, numba's and llvmlite's
    versions, the target's ``magic_tuple``: triple, CPU and its features, and
    the optimisation level); the file holds the compiled library as numba's
    own cache holds a kernel's (``serialize_using_object_code``: object code
    plus the bitcode later compiles link against), in the folder numba caches
    navlab's kernels in. A missing, unreadable or foreign file means one
    compile as before, and the file is written (atomically) for the next
    process.
    """
    from numba.core.runtime import nrtdynmod

    compile_nrt = nrtdynmod.compile_nrt_functions
    if getattr(compile_nrt, "from_cache", False) or not hasattr(nrtdynmod, "create_nrt_module"):
        return

    def compile_nrt_functions(ctx):
        ir_module, library = nrtdynmod.create_nrt_module(ctx)
        path = _runtime_file(ctx, ir_module)
        loaded = _load_runtime(ctx, path) if path else None
        if loaded is not None:
            compile_nrt_functions.loaded_from = path
            return loaded
        library.enable_object_caching()  # so that the compiled object can be written
        library.add_ir_module(ir_module)
        library.finalize()
        if path:
            _save_runtime(library, path)
        return library

    compile_nrt_functions.from_cache = True
    compile_nrt_functions.loaded_from = None
    compile_nrt_functions.__doc__ = compile_nrt.__doc__
    nrtdynmod.compile_nrt_functions = compile_nrt_functions


def _runtime_anchor():
    """A function of this module's, whose numba cache locator names the folder the runtime's file goes in."""


def _runtime_file(ctx, ir_module):
    """The runtime file's path for this IR and target, or None when numba finds no cache folder."""
    import llvmlite
    import numba
    from numba.core import config
    from numba.core.caching import FunctionCache

    try:
        folder = FunctionCache(_runtime_anchor).cache_path  # numba's locators: NUMBA_CACHE_DIR, __pycache__, ...
    except (RuntimeError, OSError):
        return None
    key = repr((numba.__version__, llvmlite.__version__, ctx.codegen().magic_tuple(), config.OPT)) + str(ir_module)
    return os.path.join(folder, f"numba_runtime-{hashlib.sha256(key.encode()).hexdigest()[:24]}.nbo")


def _load_runtime(ctx, path):
    """The runtime library unserialized from ``path``, or None when there is no usable file."""
    try:
        with open(path, "rb") as f:
            state = pickle.loads(f.read())  # noqa: S301 - written by _save_runtime, in numba's own cache folder
        library = ctx.codegen().unserialize_library(state)
        if not library.get_pointer_to_function("NRT_incref"):
            return None
        return library
    except Exception:  # noqa: BLE001 - missing, truncated or foreign: compile as numba would
        return None


def _save_runtime(library, path) -> None:
    """Write the compiled runtime library for later processes; a folder that refuses it changes nothing."""
    try:
        data = pickle.dumps(library.serialize_using_object_code(), protocol=pickle.HIGHEST_PROTOCOL)
        handle, temporary = tempfile.mkstemp(dir=os.path.dirname(path), suffix=".tmp")
        try:
            with os.fdopen(handle, "wb") as f:
                f.write(data)
            os.replace(temporary, path)  # atomic: a concurrent reader sees the old file or the whole new one
        except BaseException:
            os.unlink(temporary)
            raise
    except (OSError, ValueError, pickle.PicklingError):
        pass
