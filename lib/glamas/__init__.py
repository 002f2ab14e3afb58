"""glamas: generalized learning automata and 2observe, after De Hauwere, Vrancx and Nowe,
'Multi-Agent Systems and Large State Spaces'."""

from glamas.inlining import skip_copies_of_fresh_ir
from glamas.sources import prepare_kernel_cache

__version__ = "0.6.0"
"""Raised whenever a change alters what an experiment computes: result files record it."""

# Before any kernel is loaded: numba's cache does not notice edits to the functions a cached kernel
# calls in other files, so a change of the sources drops the whole cache, and a cache glamas cannot
# keep in step is not used at all (glamas.sources).
prepare_kernel_cache()
skip_copies_of_fresh_ir()  # compile time only: the machine code is the same (glamas.inlining)
