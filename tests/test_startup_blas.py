"""navlab.numba_start: numba finds SciPy's BLAS without ``scipy.linalg`` being imported, and
nothing that uses BLAS or ``scipy.linalg`` afterwards notices. Each check runs in a fresh process
(the preload only acts before numba's first kernel loads); the truth is numpy's own linear algebra."""

import json
import subprocess
import sys

import numpy as np


def run(code):
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_numba_blas_and_scipy_linalg_work_after_the_preload():
    got = run("""
import json, sys
from navlab.numba_start import preload_cython_blas
first = preload_cython_blas()
import numba, numpy as np

@numba.njit
def blas(a, b):
    return np.dot(a, b)

@numba.njit
def lapack(a):  # compiling a LAPACK call imports scipy.linalg.cython_lapack, and so scipy.linalg
    return np.linalg.det(a)  # one LAPACK routine (getrf): solve and inv as well cost 4 s more of compiling

a = np.array([[4.0, 1.0, 0.5], [1.0, 3.0, 0.25], [0.5, 0.25, 2.0]])
b = np.array([1.0, -2.0, 3.0])
dot = blas(a, b)
from numba.np import arraymath
linalg_before = "scipy.linalg" in sys.modules
det = lapack(a)
import scipy.linalg
from scipy.linalg import cython_blas
import scipy.linalg.cython_blas as by_dotted_name
import scipy.linalg.cython_blas  # the plain spelling reads the package's attribute
print(json.dumps({"first": first, "again": preload_cython_blas(), "have_blas": arraymath._HAVE_BLAS,
                  "linalg_before": linalg_before, "same_module": cython_blas is by_dotted_name
                  is scipy.linalg.cython_blas is sys.modules["scipy.linalg.cython_blas"],
                  "dot": dot.tolist(), "det": det,
                  "scipy_solve": scipy.linalg.solve(a, b).tolist(), "scipy_det": scipy.linalg.det(a)}))
""")
    a = np.array([[4.0, 1.0, 0.5], [1.0, 3.0, 0.25], [0.5, 0.25, 2.0]])
    b = np.array([1.0, -2.0, 3.0])
    assert got["first"] is True and got["again"] is True
    assert got["have_blas"] is True  # numba's BLAS check passed on the preloaded module
    assert got["linalg_before"] is False  # ... without importing the scipy.linalg package
    assert got["same_module"] is True  # one extension module, whichever way it is imported later
    np.testing.assert_allclose(got["dot"], a @ b, rtol=1e-12)
    np.testing.assert_allclose(got["det"], np.linalg.det(a), rtol=1e-12)
    np.testing.assert_allclose(got["scipy_solve"], np.linalg.solve(a, b), rtol=1e-12)
    np.testing.assert_allclose(got["scipy_det"], np.linalg.det(a), rtol=1e-12)


def test_no_preload_once_scipy_linalg_is_imported():
    got = run("""
import json, sys
import scipy.linalg  # its compiled parts import cython_blas the ordinary way
module = sys.modules["scipy.linalg.cython_blas"]
from navlab.numba_start import preload_cython_blas
print(json.dumps({"there": preload_cython_blas(), "untouched": sys.modules["scipy.linalg.cython_blas"] is module
                  and scipy.linalg.cython_blas is module}))
""")
    assert got == {"there": True, "untouched": True}


def test_no_preload_once_numba_has_loaded_a_kernel():
    got = run("""
import json, sys
import numba

@numba.njit
def one(x):
    return x + 1

one(1)  # numba's array implementations are loaded: its BLAS check has run
before = "scipy.linalg.cython_blas" in sys.modules
from navlab.numba_start import preload_cython_blas
print(json.dumps({"before": before, "there": preload_cython_blas()}))
""")
    assert got == {"before": True, "there": True}


def test_silent_when_scipy_cannot_be_found():
    got = run("""
import json, sys
sys.modules["scipy"] = None  # what the import system reads as 'no such package'
from navlab.numba_start import preload_cython_blas
print(json.dumps({"loaded": preload_cython_blas(), "blas": "scipy.linalg.cython_blas" in sys.modules}))
""")
    assert got == {"loaded": False, "blas": False}


def test_the_extension_file_is_found_here():
    # the preload must not be a silent no-op in navlab's own environment (the benchmark measures it)
    import importlib.machinery

    from navlab.numba_start import _extension_spec

    spec = _extension_spec()
    assert spec is not None and spec.name == "scipy.linalg.cython_blas"
    assert spec.origin.endswith(tuple(importlib.machinery.EXTENSION_SUFFIXES))
