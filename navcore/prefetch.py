"""Cache prefetch hints for numba kernels, through LLVM's ``llvm.prefetch`` (LLVM IR).

A hint never faults and changes no value: a kernel asks for the cache lines it will touch a
little later (the cells a few places ahead in the wavefront's queue) so that their memory
latency overlaps the work in between. Only the wavefront's fast variant uses it
(``wavefront.KERNEL_VARIANT``); the plain kernel beside it runs without.
"""

from __future__ import annotations

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic


def _emit_prefetch(builder, ptr, write: bool) -> None:  # type: ignore[no-untyped-def]
    i8p = ir.IntType(8).as_pointer()
    i32 = ir.IntType(32)
    fn = cgutils.get_or_insert_function(
        builder.module, ir.FunctionType(ir.VoidType(), [i8p, i32, i32, i32]),
        "llvm.prefetch.p0i8")
    # (address, 1 = for writing / 0 = for reading, locality 3 = keep in all levels, data cache)
    builder.call(fn, [builder.bitcast(ptr, i8p), i32(1 if write else 0), i32(3), i32(1)])


@intrinsic
def prefetch_write(typingctx, arr, i):  # type: ignore[no-untyped-def]
    """Fetch element ``i`` of a 1-D array into cache, for writing (``prefetchw``)."""
    if not (isinstance(arr, types.Array) and arr.ndim == 1):
        return None

    def codegen(context, builder, sig, args):  # type: ignore[no-untyped-def]
        a = context.make_array(sig.args[0])(context, builder, args[0])
        _emit_prefetch(builder, builder.gep(a.data, [args[1]]), write=True)
        return context.get_dummy_value()
    return types.none(arr, i), codegen
