"""numba's inlining of ``inline="always"`` functions without its two defensive copies: the same
machine code, compiled in less time.

At every call site of such a function, numba builds the callee's IR afresh from its bytecode and
then deep-copies it twice before splicing it in (``InlineWorker.inline_ir``): once so that the
splice does not mutate the IR it was given, once to hand back an untouched copy that every caller
drops. A fresh IR needs neither; and as numba copies it block by block, every block's copy copies
the callee's whole variable scope again, so the cost grows with the square of the callee's size
and with each level of nesting. For 2observe's kernels the copies were 30 % of the compile time.

:func:`skip_copies_of_fresh_ir` makes ``inline_function`` (the path of ``inline="always"``) splice
the fresh IR itself. Every other use of ``inline_ir`` (numba's own overloads, whose IR is kept and
reused) still copies. The small runs check it: every experiment's small run gives the committed
bits (``python -m glamas.precompile --check``).
"""

import types

from numba.core import inline_closurecall

_NO_COPY = types.SimpleNamespace(deepcopy=lambda ir_part, memo=None: ir_part)
NUMBA_INLINE_FUNCTION = inline_closurecall.InlineWorker.inline_function
"""numba's own, which copies."""


def _inline_fresh_function(worker, caller_ir, block, i, function, arg_typs=None):
    """numba's ``InlineWorker.inline_function``, with ``inline_ir``'s copies of the fresh IR skipped
    (numba compiles under one global lock, so no other compilation sees the swapped module)."""
    callee_ir = worker.run_untyped_passes(function)
    copy_module = inline_closurecall.copy
    inline_closurecall.copy = _NO_COPY
    try:
        return worker.inline_ir(caller_ir, block, i, callee_ir, function.__code__.co_freevars, arg_typs=arg_typs)
    finally:
        inline_closurecall.copy = copy_module


def skip_copies_of_fresh_ir() -> None:
    """Install :func:`_inline_fresh_function` in numba (once per process; a numba whose inliner
    no longer has this shape is left as it is)."""
    worker = inline_closurecall.InlineWorker
    if hasattr(inline_closurecall, "copy") and hasattr(worker, "inline_function"):
        worker.inline_function = _inline_fresh_function
