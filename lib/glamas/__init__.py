"""glamas: generalized learning automata and 2observe, after De Hauwere, Vrancx and Nowe,
'Multi-Agent Systems and Large State Spaces'."""

from glamas.sources import refresh_kernel_cache

__version__ = "0.3.0"
"""Raised whenever a change alters what an experiment computes: result files record it."""

# Before any kernel is loaded: numba's cache does not notice edits to the functions a cached kernel
# calls in other files, so a change of the sources drops the whole cache (glamas.sources).
refresh_kernel_cache()
