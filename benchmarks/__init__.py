"""Speed benchmarks: glamas's compiled kernels against plain-Python references (``python_*``) and a
plain-C reference (``reference_gridworld.c``) of the same work. Run each from the repository root as
``python -m benchmarks.bench_<name>`` (``--quick``: small sizes); ``make benchmark`` runs them all.

``kernels`` is the one module that builds the compiled kernels' arguments and runs them.
"""
