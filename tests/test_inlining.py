"""glamas.inlining: numba splices an ``inline="always"`` function's fresh IR without copying it, and
compiles the same machine code as numba's own inliner. (That every kernel still gives its experiment's
committed bits is checked by the small runs: ``python -m glamas.precompile --check``.)"""

import copy
import re

import numpy as np
from numba import njit
from numba.core import inline_closurecall, ir

import glamas  # noqa: F401  (installs glamas.inlining)
from glamas import inlining


@njit(inline="always")
def _clipped(x, low, high):
    return min(max(x, low), high)


@njit(inline="always")
def _scaled_sum(values, factor):
    total = 0.0
    for v in values:
        total += _clipped(v * factor, -1.0, 1.0)  # an inline function inside an inline function
    return total


def _two_sums(values):
    return _scaled_sum(values, 0.5) + _scaled_sum(values, 2.0)


def _compiled(values) -> tuple[float, str]:
    """The value and the machine code of ``_two_sums`` compiled afresh: the instructions of its
    first function, the compiled body (symbols carry numba's count of compilations: left out)."""
    kernel = njit(_two_sums)
    value, assembly = kernel(values), kernel.inspect_asm(kernel.signatures[0])
    body = assembly.split("@function\n", 1)[1]
    return value, re.sub(r"B\d+v\d+", "B", body.split(".Lfunc_end0:", 1)[0])


def test_glamas_installs_the_inliner():
    assert inline_closurecall.InlineWorker.inline_function is inlining._inline_fresh_function


def test_no_block_is_copied_and_the_code_is_numbas_own(monkeypatch):
    values = np.array([-3.0, -0.4, 0.1, 0.7, 5.0])
    real_deepcopy, copied_blocks = copy.deepcopy, []

    def deepcopy(thing, memo=None):
        copied_blocks.append(isinstance(thing, ir.Block))
        return real_deepcopy(thing, memo)

    monkeypatch.setattr(copy, "deepcopy", deepcopy)
    ours, our_code = _compiled(values)
    assert not any(copied_blocks)
    assert ours == _two_sums(values)  # in Python, calling the compiled pieces
    assert inline_closurecall.copy is copy  # numba's overloads, whose IR is kept, still copy

    monkeypatch.setattr(inline_closurecall.InlineWorker, "inline_function", inlining.NUMBA_INLINE_FUNCTION)
    numbas, numbas_code = _compiled(values)
    assert any(copied_blocks)  # the check above could see a copy
    assert (numbas, numbas_code) == (ours, our_code)
