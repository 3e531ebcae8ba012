"""CHOLMOD's solve of a block of right-hand sides at once, on the factor of the cvxopt wheel.

cvxopt's ``cholmod.solve`` solves one column at a time: k columns cost k solves (its
``spsolve``, for a sparse right-hand side, is slower still). CHOLMOD itself solves a
block of columns in one sweep of the factor, with level-3 BLAS on each supernode, and
the wheel ships that CHOLMOD (``cvxopt.libs/libcholmod-*.so``) with OpenBLAS. This module
calls its ``cholmod_l_solve`` directly on cvxopt's factor, through :mod:`ctypes` (found
through the handle of cvxopt's ``cholmod`` extension, so the very library it links): the
factor is the ``cholmod_factor *`` in cvxopt's capsule, the right-hand sides a
``cholmod_dense`` view of a Fortran-ordered NumPy array, and the solution is copied out
and freed by CHOLMOD.

It is an accelerator with a reference: :class:`BlockSolver` is only used after it has
reproduced cvxopt's column-by-column solve on the factor at hand (two random columns,
to 1e-12 of their size; measured 1e-15), and any failure (no such library on this
platform, a missing symbol, a capsule that is not a real factor, an error returned by
CHOLMOD) leaves the column-by-column solve in place. Measured (2026-11-26, one thread,
per column against one column by cvxopt): 0.72–0.82 for two columns and 0.25–0.26 for
eight, on a 2D matrix of 49.9k DOF and on a 3D Tet10 step matrix of 24.1k DOF
(docs/benchmarks.md, "Block solves"); the Delassus operator and the static problem set
up 3.2 to 3.7 times faster.
"""

from __future__ import annotations

import ctypes
import logging
import threading
from functools import cache
from typing import Any

import numpy as np

from ..typing import FloatArray

log = logging.getLogger(__name__)

#: columns solved in one call: more gain little and, on small factors, spill the cache
#: (per column at 12.8k DOF: 0.64 of one column at 8 columns, 0.71 at 16, 0.82 at 32)
BLOCK = 16

#: below this many DOF two or three columns are solved one at a time: the small
#: supernodes of a small factor leave the level-3 calls nothing to gain (2D, 12.8k DOF:
#: two columns 1.09 and three 1.05 times as long as as many single solves; 49.9k DOF:
#: 0.72 and 0.54; a 3D Tet10 step matrix of 24.1k DOF: 0.82 and 0.63)
SMALL_BLOCK_MIN_DOF = 20_000

#: below this many DOF every column is solved alone: a solve takes well under a
#: millisecond there, and the models keep the bits they had before blocks were used
BLOCK_MIN_DOF = 5_000


def pays(n: int, k: int) -> bool:
    """Whether k columns of a factor of n DOF are solved as a block (a rule on the
    sizes only, so that on one installation the same problem always takes the same path
    and bits)."""
    if n < BLOCK_MIN_DOF:
        return False
    return k >= 4 or (k >= 2 and n >= SMALL_BLOCK_MIN_DOF)


_CHOLMOD_A = 0  # solve A x = b
_CHOLMOD_REAL = 1
_CHOLMOD_DOUBLE = 0


class _Dense(ctypes.Structure):
    """``cholmod_dense`` (CHOLMOD 3.x and later)."""

    _fields_ = [
        ("nrow", ctypes.c_size_t),
        ("ncol", ctypes.c_size_t),
        ("nzmax", ctypes.c_size_t),
        ("d", ctypes.c_size_t),
        ("x", ctypes.c_void_p),
        ("z", ctypes.c_void_p),
        ("xtype", ctypes.c_int),
        ("dtype", ctypes.c_int),
    ]


#: byte offsets in ``cholmod_common`` (CHOLMOD 3 to 5) of the defaults that identify its
#: layout (zrelax = 0.8, 0.1, 0.05; nrelax = 4, 16, 48) and of ``print`` (default 3)
_ZRELAX, _NRELAX, _PRINT = 80, 104, 144


def _quiet(common: ctypes.Array[ctypes.c_char]) -> bool:
    """Set CHOLMOD's print level to 0 in a started ``common`` (its errors then come back
    as a NULL result only, not as lines on the C stdout), where its layout is the known
    one; True if it was set."""
    z = list((ctypes.c_double * 3).from_buffer(common, _ZRELAX))
    r = list((ctypes.c_size_t * 3).from_buffer(common, _NRELAX))
    level = ctypes.c_int.from_buffer(common, _PRINT)
    if z != [0.8, 0.1, 0.05] or r != [4, 16, 48] or level.value != 3:
        return False
    level.value = 0
    return True


class BlockSolver:
    """``cholmod_l_solve`` of the CHOLMOD library that cvxopt's factors live in. Calls
    are serialised (one ``cholmod_common`` is shared; ctypes releases the GIL)."""

    def __init__(self, lib: ctypes.CDLL) -> None:
        self._lib = lib
        self._lock = threading.Lock()
        lib.cholmod_l_start.argtypes = [ctypes.c_void_p]
        lib.cholmod_l_start.restype = ctypes.c_int
        lib.cholmod_l_solve.argtypes = [ctypes.c_int, ctypes.c_void_p,
                                        ctypes.POINTER(_Dense), ctypes.c_void_p]  # fmt: skip
        lib.cholmod_l_solve.restype = ctypes.POINTER(_Dense)
        lib.cholmod_l_free_dense.argtypes = [ctypes.POINTER(ctypes.POINTER(_Dense)),
                                             ctypes.c_void_p]  # fmt: skip
        lib.cholmod_l_free_dense.restype = ctypes.c_int
        # cholmod_common: its size differs between versions; far more than any needs
        self._common = ctypes.create_string_buffer(1 << 16)
        if not lib.cholmod_l_start(self._common):
            raise OSError("cholmod_l_start failed")
        if not _quiet(self._common):
            log.debug("cholmod_common of an unknown layout: its print level is kept")
        # the capsule functions of a private handle: pythonapi's prototypes stay as they are
        api = ctypes.PyDLL(None)
        get_name, get_pointer = api.PyCapsule_GetName, api.PyCapsule_GetPointer
        get_name.restype, get_name.argtypes = ctypes.c_char_p, [ctypes.py_object]
        get_pointer.restype = ctypes.c_void_p
        get_pointer.argtypes = [ctypes.py_object, ctypes.c_char_p]
        self._name, self._pointer = get_name, get_pointer

    def factor_pointer(self, F: Any) -> int:
        """The ``cholmod_factor *`` of a cvxopt factor of a real matrix."""
        name = self._name(F)
        if not name or not name.startswith(b"CHOLMOD FACTOR D"):
            raise TypeError(f"not the CHOLMOD factor of a real matrix: {name!r}")
        return int(self._pointer(F, name))

    def solve(self, L: int, B: FloatArray) -> FloatArray:
        """X = A⁻¹ B for B (n, k), A = L Lᵀ the factor at ``L`` (one call)."""
        B = np.asfortranarray(B, dtype=float)
        n, k = B.shape
        rhs = _Dense(n, k, n * k, n, B.ctypes.data, None, _CHOLMOD_REAL, _CHOLMOD_DOUBLE)
        with self._lock:
            X = self._lib.cholmod_l_solve(_CHOLMOD_A, L, ctypes.byref(rhs), self._common)
            if not X:
                raise ArithmeticError("cholmod_l_solve returned no solution")
            try:
                x = X.contents
                if (x.nrow, x.ncol, x.xtype) != (n, k, _CHOLMOD_REAL) or x.d < n:
                    raise ArithmeticError("cholmod_l_solve returned a solution of another shape")
                buf = ctypes.cast(x.x, ctypes.POINTER(ctypes.c_double))
                out = np.ctypeslib.as_array(buf, shape=(k, x.d))[:, :n].T.copy()
            finally:
                self._lib.cholmod_l_free_dense(ctypes.byref(X), self._common)
        return out


@cache
def block_solver() -> BlockSolver | None:
    """The block solver of the installed cvxopt wheel, or None where it cannot be
    loaded (another platform's layout, a build without the bundled library)."""
    try:
        import cvxopt.cholmod
    except ImportError:
        return None
    try:
        # the extension's own handle: its symbols resolve to the CHOLMOD it was linked
        # with (dlsym searches a library's dependencies), wherever that library lives
        return BlockSolver(ctypes.CDLL(cvxopt.cholmod.__file__))
    except (OSError, AttributeError) as exc:
        log.debug("CHOLMOD block solve unavailable (%s): column-by-column solves", exc)
        return None


__all__ = ["BLOCK", "BLOCK_MIN_DOF", "SMALL_BLOCK_MIN_DOF", "BlockSolver", "block_solver",
           "pays"]  # fmt: skip
