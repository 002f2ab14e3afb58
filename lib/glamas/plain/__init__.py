"""The chapter's algorithms step by step in plain Python: lists, loops and one random source, no
NumPy, nothing compiled. Read these for the algorithm; the compiled kernels of
:mod:`glamas.learners` are their fast path, and play the very same episodes on the same random
numbers (tests/test_benchmark_references.py).

- :mod:`glamas.plain.gla`: a GLA's action and update (Section 4.1, eq. 12-15).
- :mod:`glamas.plain.lineworld`: the line world's experiments 1 and 2 (Section 4.2, Fig. 5-7).
- :mod:`glamas.plain.gridworld`: the gridworld's rules and every gridworld learner's step: Q-learning
  (Alg. 3, eq. 11) for the independent, joint-state and MMDP learners, 2observe (Alg. 4) for two
  agents and for N, sparse cooperative Q-learning and CQ-learning.
- :mod:`glamas.plain.many_agents`: the N-agent steps through the index of cells, as the kernels
  take them at scale.

The benchmarks time them against the kernels (benchmarks/bench_*.py). Nothing in the library
imports them: a result's record of code never holds them.
"""
