"""The wavefront's four pushes as one vector step with a compress (LLVM IR).

The fast kernel variant on AVX-512 targets (``wavefront.KERNEL_VARIANT``): the four neighbours'
push tests as one 4-lane compare, their gates written back, and the pushed cells appended in
neighbour order (left, right, up, down): packed to the front of a register
(``llvm.experimental.vector.compress``, one ``vpcompressd`` on AVX-512) and stored as a whole.
Same pushes in the same order as the plain ``_push_next`` / ``_push_over`` beside the kernel,
so the same potentials; tests run both on every host (where the CPU lacks the instruction, LLVM
expands it).
"""

from __future__ import annotations

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.core.extending import intrinsic

# the gate's slot in a cell's 8-byte record (wavefront.GATE; wavefront checks they agree)
GATE = 1


def _push4_codegen(above: bool):  # type: ignore[no-untyped-def]
    def codegen(context, builder, sig, args):  # type: ignore[no-untyped-def]
        rec = context.make_array(sig.args[0])(context, builder, args[0])
        queue = context.make_array(sig.args[1])(context, builder, args[1])
        count, p, pms, cells = args[2], args[3], args[4:8], args[8:12]
        f32, i32, i64 = ir.FloatType(), ir.IntType(32), ir.IntType(64)
        v4f, v4i = ir.VectorType(f32, 4), ir.VectorType(i32, 4)
        g = pm = ir.Constant(v4f, None)
        idx = ir.Constant(v4i, None)
        ptrs = []
        for k in range(4):
            slot = builder.add(builder.shl(cells[k], i64(1)), i64(GATE))
            ptrs.append(builder.gep(rec.data, [slot]))
            g = builder.insert_element(g, builder.load(ptrs[k]), i32(k))
            pm = builder.insert_element(pm, pms[k], i32(k))
            idx = builder.insert_element(idx, builder.trunc(cells[k], i32), i32(k))
        pv = builder.shuffle_vector(builder.insert_element(ir.Constant(v4f, None), p, i32(0)),
                                    ir.Constant(v4f, None), ir.Constant(v4i, [0, 0, 0, 0]))
        zero = ir.Constant(v4f, [0.0] * 4)
        if above:  # to overflow when idle: the gate turns negative
            ok = builder.and_(builder.fcmp_ordered(">", pm, builder.fadd(pv, g)),
                              builder.fcmp_ordered(">", g, zero))
            g = builder.select(ok, builder.fsub(zero, g), g)
        else:  # to next, also from overflow: the gate turns +inf
            fabs = cgutils.get_or_insert_function(builder.module, ir.FunctionType(v4f, [v4f]),
                                                  "llvm.fabs.v4f32")
            ok = builder.fcmp_ordered(">", pm, builder.fadd(pv, builder.call(fabs, [g])))
            g = builder.select(ok, ir.Constant(v4f, [float("inf")] * 4), g)
        for k in range(4):
            builder.store(builder.extract_element(g, i32(k)), ptrs[k])
        # the pushed cells packed to the front of a register, then all four lanes stored at the
        # queue's end (a buffer always has four places past its queue: border cells are never
        # queued, and propagate keeps room in the overflow): the compressing store to memory
        # is microcoded on AMD Zen 4 (llvm/llvm-project#133568); merge-masking into the cells
        # themselves avoids the zero-masked form's false dependency on Zen 4 and 5
        v4b = ir.VectorType(ir.IntType(1), 4)
        fn = cgutils.get_or_insert_function(
            builder.module, ir.FunctionType(v4i, [v4i, v4b, v4i]),
            "llvm.experimental.vector.compress.v4i32")
        packed = builder.call(fn, [idx, ok, idx])
        dst = builder.bitcast(builder.gep(queue.data, [count]), v4i.as_pointer())
        builder.store(packed, dst, align=4)
        pop = cgutils.get_or_insert_function(
            builder.module, ir.FunctionType(ir.IntType(4), [ir.IntType(4)]), "llvm.ctpop.i4")
        return builder.add(count, builder.zext(
            builder.call(pop, [builder.bitcast(ok, ir.IntType(4))]), i64))
    return codegen


def _push4_typing(above: bool):  # type: ignore[no-untyped-def]
    def typer(typingctx, rec, queue, count, p, l, r, u, d, ml, mr, mu, md):  # type: ignore
        """Apply the push rule to the four neighbours (old potentials l, r, u, d; cells ml, mr, mu,
        md) of a cell that got potential p: update their gates in the records ``rec`` and append
        the pushed ones to ``queue`` (int32) at ``count``; returns the new count (uintp)."""
        ok = (isinstance(rec, types.Array) and rec.dtype == types.float32
              and isinstance(queue, types.Array) and queue.dtype == types.int32
              and count == types.uintp and p == types.float32
              and all(v == types.float32 for v in (l, r, u, d))
              and all(m == types.uintp for m in (ml, mr, mu, md)))
        if not ok:
            return None
        return (types.uintp(rec, queue, count, p, l, r, u, d, ml, mr, mu, md),
                _push4_codegen(above))
    return typer


push4_next = intrinsic(_push4_typing(False))
push4_over = intrinsic(_push4_typing(True))
