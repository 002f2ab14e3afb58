"""The runs of one kernel (:class:`Batch`), the outputs they fill, and the chunks of runs that
are the jobs.

A run kernel is the compiled function of one run, ``kernel(*inputs, *outputs_of_the_run, state)``
with ``@njit(cache=True, nogil=True)``: it reads the shared ``inputs`` and its own generator
``state`` and writes only its run's slice of each output.
"""

import itertools
from dataclasses import dataclass

import numpy as np

from glamas.errors import UserError
from glamas.parallel.backends import Dask, cores
from glamas.rng import check_seed


class NonFiniteError(UserError, FloatingPointError):
    """A run produced NaN or infinite values: a setting drove the learning out of range."""


@dataclass(frozen=True)
class Evaluation:
    """Episodes played right after each run of a batch, in the same job, from copies of what the
    run learned: the kernel called again with ``inputs`` (its inputs with learning off), the run's
    log replaced by this evaluation's own, on a stream of its own. The learned tables need not
    leave the worker (they may be a :class:`Scratch`)."""

    inputs: tuple
    """The kernel's inputs for the evaluation."""
    log: int
    """The position of the kernel's log among its outputs: the evaluation fills its own there."""
    seed: int
    """The master seed of the evaluation's streams (:func:`glamas.rng.chunk_states`)."""

    def key(self) -> tuple:
        """What makes its outputs what they are (:func:`glamas.parallel.memo.key_of`)."""
        return self.inputs, self.log, self.seed


@dataclass(frozen=True)
class Batch:
    """The runs of one run kernel: ``kernel(*inputs, *outputs_of_the_run, state)`` for every run,
    the runs' streams drawn from master seed ``seed`` (:func:`glamas.parallel.run_batches`), each
    run followed by the :attr:`evaluations` of what it learned."""

    kernel: object
    """The compiled run kernel (``@njit(cache=True, nogil=True)``)."""
    inputs: tuple
    """What every run reads."""
    outputs: tuple
    """Arrays whose first axis is the run, each run filling its own slice, or :class:`Scratch`
    for an output that the caller does not keep."""
    seed: int
    """The master seed of the runs' streams (:func:`glamas.rng.chunk_states`)."""
    evaluations: tuple = ()
    """:class:`Evaluation` s played after each run; their logs are the last outputs, one each, in
    order (the kernel's own outputs come first)."""


@dataclass(frozen=True)
class Scratch:
    """An output that the caller does not keep, in place of its array in :attr:`Batch.outputs`:
    each run fills an array of its own (``shape[1:]`` of ``dtype``, starting at ``value``) that
    is dropped after the run. Nothing of it is allocated in the caller or sent back: an
    experiment that wants only the learning curves of a joint learner of four agents would
    otherwise allocate and receive gigabytes of Q tables."""

    shape: tuple
    """(runs, ...): the run axis, then one run's array."""
    dtype: np.dtype
    value: object
    """Every element's value at the start of a run."""

    @property
    def ndim(self) -> int:
        return len(self.shape)

    def runs(self, start: int, stop: int) -> "Scratch":
        """Runs ``start`` to ``stop - 1`` (as slicing an array's first axis; ``start`` < runs)."""
        return Scratch((min(stop, self.shape[0]) - start, *self.shape[1:]), self.dtype, self.value)


def check_batch(batch: Batch) -> None:
    check_seed(batch.seed)
    for evaluation in batch.evaluations:
        check_seed(evaluation.seed)
    if any(out.ndim < 2 for out in batch.outputs):
        raise UserError("every output needs an axis of runs and an array per run (ndim >= 2), got shapes "
                         f"{[out.shape for out in batch.outputs]}")


def check_finite(kernel, start: int, filled: tuple) -> None:
    """Raise :class:`NonFiniteError` if a floating-point output of runs ``start, ...`` holds NaN
    or infinity: a learning rate, K, reward or penalty too large makes the updates overflow, and
    every later number would be meaningless."""
    for k, part in enumerate(filled):
        if part is None or not np.issubdtype(part.dtype, np.floating):
            continue
        finite = np.isfinite(part.reshape(part.shape[0], -1)).all(axis=1)
        if not finite.all():
            run = start + int(np.argmin(finite))
            function = getattr(kernel, "py_func", kernel)
            name = f"{getattr(function, '__module__', '?')}.{getattr(function, '__qualname__', function)}"
            raise NonFiniteError(f"run {run} of {name} produced NaN or infinite values in its output {k}: "
                                 "a learning rate, K, reward or penalty is too large for the learning to stay "
                                 "finite; lower it")


def chunk_size(n_runs: int, backend) -> int:
    """Runs per job: about four jobs per local worker, so that runs of unequal length even out
    while a job stays long next to sending it; 8 runs on a cluster of unknown size."""
    if isinstance(backend, Dask):
        return 8
    return max(1, -(-n_runs // (4 * (backend.workers or cores()))))


def jobs_of(batches: list, to_run: list, backend, chunk: int | None) -> list:
    """The jobs of batches ``to_run`` (their numbers in ``batches``): ``(batch number, start, stop,
    the outputs' initial slices)``, ``chunk`` runs each (None: :func:`chunk_size`)."""
    per_batch = []
    for k in to_run:
        batch = batches[k]
        n_runs = batch.outputs[0].shape[0]
        size = chunk_size(n_runs, backend) if chunk is None else chunk
        per_batch.append([(k, start, min(start + size, n_runs), tuple(_runs_of(out, start, start + size)
                                                                       for out in batch.outputs))
                          for start in range(0, n_runs, size)])
    # The batches' jobs taken in turn: the workers start on different kernels, so that each
    # compiles (or loads) a different one at first instead of all the same.
    return [job for turn in itertools.zip_longest(*per_batch) for job in turn if job is not None]


def _runs_of(out, start: int, stop: int):
    """Runs ``start`` to ``stop - 1`` of an output: an array's slice, or a Scratch's."""
    return out.runs(start, stop) if isinstance(out, Scratch) else out[start:stop]
