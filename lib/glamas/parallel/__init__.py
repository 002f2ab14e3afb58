"""Independent runs in parallel: one generator state per run, chunks of runs mapped to workers.

A run kernel is the compiled function of one run (:mod:`glamas.parallel.batch`). A job is one
chunk of runs, and the ``workers`` argument of :func:`run_batches` and :func:`run_many` (and of
every experiment's ``run``) picks who runs the jobs: local processes by default (loky, joblib's
pool of reusable workers; an int or None is their number, see :class:`Processes`), threads in
this process (:class:`Threads`), or a Dask distributed cluster (:class:`Dask`, optional extra
``dask``). A job derives its runs' generator states from the master seed and its run indices
(:func:`glamas.rng.chunk_states`), so every backend, number of workers and chunking gives
bit-identical results. A process may keep the outputs of the batches it runs, to fill an
identical batch with instead of running it (:func:`reuse_batches`).

Modules: ``backends`` (who runs the jobs), ``batch`` (the runs of one kernel, cut into jobs),
``job`` (one job, and what travels to a worker), ``local`` (threads, processes), ``dask``,
``memo`` (batches run before), ``runner`` (:func:`run_many`).
"""

from glamas.parallel.backends import (BACKENDS, BackendError, Dask, Processes, Threads, backend, cores,
                                      require_dask)
from glamas.parallel.batch import Batch, Evaluation, NonFiniteError, Scratch, check_finite, chunk_size
from glamas.parallel.dask import connect
from glamas.parallel.job import fill_chunk, run_chunk
from glamas.parallel.memo import reuse_batches
from glamas.parallel.runner import run_batches, run_many

__all__ = ["BACKENDS", "BackendError", "Batch", "Dask", "Evaluation", "NonFiniteError", "Processes", "Scratch", "Threads",
           "backend", "check_finite", "chunk_size", "connect", "cores", "fill_chunk", "reuse_batches",
           "require_dask", "run_batches", "run_chunk", "run_many"]
