"""glamas: generalized learning automata and 2observe, after De Hauwere, Vrancx and Nowe,
'Multi-Agent Systems and Large State Spaces'."""

__version__ = "0.1.0"
