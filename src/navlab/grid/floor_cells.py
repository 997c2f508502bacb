"""The cell a coordinate falls in, as Python's ``x // res`` says, for compiled code.

Numba compiles a float ``//`` the way CPython's ``float_divmod`` computes it,
through a call to ``fmod`` that it cannot inline (``numba_fmod`` in its
helper library): on PythonRobotics' demo query that call alone was 9 % of
Hybrid A*'s time (``perf record``), two per child the search generates.
:func:`floor_div` gives the same number without it.
"""

from __future__ import annotations

import math

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

from ..jit import njit


@intrinsic
def _fma(typingctx, a, b, c):
    """``a·b + c`` rounded once (LLVM's ``llvm.fma.f64``: one instruction where the CPU has FMA)."""
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        double = ir.DoubleType()
        fn = cgutils.get_or_insert_function(builder.module, ir.FunctionType(double, [double] * 3), "llvm.fma.f64")
        return builder.call(fn, args)

    return sig, codegen


@njit(cache=True)
def floor_div(x: float, step: float) -> float:
    """``x // step`` for finite ``x`` and ``step > 0``: the floor of the exact quotient, as Python's.

    The rounded quotient ``x / step`` can land on a whole number ``n`` when the
    exact one lies just below it (``1.0 / 0.1`` is 10.0, ``1.0 // 0.1`` is
    9.0); it cannot land below a whole number the exact one reaches, because
    rounding is monotonic and whole numbers are representable. So the floor of
    the rounded quotient is the answer or one more, and the sign of the
    remainder ``x − q·step``, computed with a single rounding (which keeps a
    sign), tells which. Exact while ``|x / step| < 2⁵³``.
    """
    q = math.floor(x / step)
    if _fma(-q, step, x) < 0.0:
        q -= 1.0
    return q
