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
- Each cached library also holds its code as LLVM bitcode, for later
  compiles that link against it, and numba parses it at load to list the
  library's symbols: about half of a kernel's load (20 of 46 ms for
  ``navlab plan clutter``'s four kernels).

:func:`cached_loads_without_registries` switches all five off for the rest of
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

import numpy as np

#: ELF64 section header and symbol table entry (the System V gABI, "Sections" and "Symbol Table")
_ELF64_SECTION = np.dtype([("name", "<u4"), ("type", "<u4"), ("flags", "<u8"), ("addr", "<u8"), ("offset", "<u8"),
                           ("size", "<u8"), ("link", "<u4"), ("info", "<u4"), ("addralign", "<u8"),
                           ("entsize", "<u8")])
_ELF64_SYMBOL = np.dtype([("name", "<u4"), ("info", "u1"), ("other", "u1"), ("shndx", "<u2"), ("value", "<u8"),
                          ("size", "<u8")])
_SHT_SYMTAB, _SHN_UNDEF, _STT_OBJECT, _STT_FUNC = 2, 0, 1, 2

#: the numba releases whose private loading pieces the switches were read against and tested with
#: (tests/test_numba_cached_loads.py); another release loads numba's own way until checked and added here
CHECKED_NUMBA = ("0.68.",)


def cached_loads_without_registries() -> bool:
    """Let numba load cached functions without its registries, environments' modules, extensions or runtime compile.

    For a process of navlab's own (see the module's docstring): it changes
    numba for the rest of the process, not only for navlab's kernels. Call
    it once numba is imported; later calls do nothing.

    Returns
    -------
    bool
        True when cached loads skip the registries from now on; False,
        changing nothing, when this numba is not a version the switches were
        checked against (:data:`CHECKED_NUMBA`: they replace private pieces of
        numba's) or lacks the pieces they call: its own loads then run as they
        always do.
    """
    import numba
    from numba.core import caching
    from numba.core.runtime import rtsys

    cache = caching.Cache
    if getattr(cache.load_overload, "skips_registries", False):
        return True
    if not numba.__version__.startswith(CHECKED_NUMBA):
        return False
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
    _linking_modules_on_demand()
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


def _linking_modules_on_demand() -> None:
    """Parse a cached library's linking bitcode when a compile links against it, not when it loads.

    numba's ``CPUCodeLibrary._unserialize`` parses the library's bitcode at
    load (the module other libraries link in, ``_get_module_for_linking``)
    and walks its functions and globals through llvmlite to record the
    symbols the library defines: the execution engine is asked for an address
    only when that record has the name (``get_pointer_to_function``). The
    replacement reads those names from the object code's own symbol table
    (:func:`_elf_defined_symbols`, 0.5 ms against 25 ms for the tree kernel;
    the same names, which a test checks against numba's walk) and parses the
    bitcode in ``_get_module_for_linking``, the one place that uses it. Object
    code that is not 64-bit little-endian ELF loads numba's way.
    """
    from numba.core import codegen

    library_class = codegen.CPUCodeLibrary
    unserialize = library_class._unserialize  # noqa: SLF001 - a classmethod, bound to the class
    if getattr(unserialize, "links_on_demand", False) or not hasattr(library_class, "_get_module_for_linking"):
        return
    module_for_linking = library_class._get_module_for_linking  # noqa: SLF001

    def _unserialize(cls, codegen_, state):
        name, kind, data = state
        symbols = _elf_defined_symbols(data[0]) if kind == "object" else None
        if symbols is None:
            return unserialize.__func__(cls, codegen_, state)
        object_code, linking_bitcode = data
        library = codegen_.create_library(name)  # numba's own steps for an "object" state, but the parse
        library.enable_object_caching()
        library._set_compiled_object(object_code)  # noqa: SLF001
        library._linking_bitcode = linking_bitcode  # noqa: SLF001 - parsed by _get_module_for_linking
        library._finalize_final_module()  # noqa: SLF001
        codegen_._engine._defined_symbols |= symbols  # noqa: SLF001 - what _load_defined_symbols would record
        return library

    def _get_module_for_linking(self):
        bitcode = getattr(self, "_linking_bitcode", None)
        if bitcode is not None and self._shared_module is None:  # noqa: SLF001
            import llvmlite.binding as ll

            self._shared_module = ll.parse_bitcode(bitcode)  # noqa: SLF001 - as numba's load would have set it
            self._linking_bitcode = None
        return module_for_linking(self)

    _unserialize.links_on_demand = True
    library_class._unserialize = classmethod(_unserialize)  # noqa: SLF001
    library_class._get_module_for_linking = _get_module_for_linking  # noqa: SLF001


def _elf_defined_symbols(object_code):
    """The names of the functions and data objects an ELF64 little-endian object file defines, or None.

    None when ``object_code`` is not such a file (another platform's object
    format, or a truncated one, or one without a symbol table): the caller
    then walks the bitcode as numba does. Symbols of every binding are listed, as numba lists internal
    functions too; sections, files and undefined symbols are not.
    """
    try:
        if len(object_code) < 64 or bytes(object_code[:6]) != b"\x7fELF\x02\x01":  # magic, 64-bit, little-endian
            return None
        table_offset = int.from_bytes(object_code[0x28:0x30], "little")
        count = int.from_bytes(object_code[0x3C:0x3E], "little")
        sections = np.frombuffer(object_code, _ELF64_SECTION, count=count, offset=table_offset)
        tables = sections[sections["type"] == _SHT_SYMTAB]
        if not len(tables):
            return None  # an object file numba wrote has one; this one is not what it seems
        names = set()
        for table in tables:
            symbols = np.frombuffer(object_code, _ELF64_SYMBOL, count=int(table["size"]) // _ELF64_SYMBOL.itemsize,
                                    offset=int(table["offset"]))
            strings_section = sections[table["link"]]
            start = int(strings_section["offset"])
            strings = bytes(object_code[start:start + int(strings_section["size"])])
            kind = symbols["info"] & 0xF
            wanted = (symbols["shndx"] != _SHN_UNDEF) & (symbols["name"] != 0) & \
                ((kind == _STT_FUNC) | (kind == _STT_OBJECT))
            for offset in symbols["name"][wanted].tolist():
                names.add(strings[offset:strings.index(b"\0", offset)].decode())
        return names
    except (ValueError, IndexError, TypeError, UnicodeDecodeError):
        return None
