"""One job: a chunk of runs filled, in the calling process or in a worker, and what is sent to a
worker process for it: the kernel by name, the inputs and the outputs' initial slices."""

import importlib
from dataclasses import dataclass, replace

import numpy as np

from glamas.errors import UserError
from glamas.parallel.batch import Scratch
from glamas.rng import chunk_states


def fill_chunk(kernel, inputs: tuple, seed: int, start: int, stop: int, initial: tuple,
               copy: bool = True, evaluations: tuple = ()) -> tuple[int, tuple]:
    """One job: runs ``start`` to ``stop - 1`` of a sweep, each followed by ``evaluations``
    (:class:`glamas.parallel.batch.Evaluation`, whose logs are the last outputs); returns
    ``(start, filled outputs)``.

    ``initial`` are the outputs' initial slices (some kernels read them, e.g. initial Q values).
    With ``copy`` the job fills copies: the caller's arrays stay untouched until it writes the
    result back, and jobs running at once never write to one cache line (which would slow them
    down). Without, it fills ``initial`` itself: arrays the job owns, or the caller's when one
    job runs at a time in the caller's process (no copy of tables that may take gigabytes).
    A :class:`Scratch` (or a :class:`Filled` in transit) becomes an array of the job's own;
    a Scratch's filled output is returned as None.
    """
    outputs = tuple(_array_of(x, copy) for x in initial)
    learned, logs = outputs[:len(outputs) - len(evaluations)], outputs[len(outputs) - len(evaluations):]
    evaluation_states = [chunk_states(evaluation.seed, start, stop) for evaluation in evaluations]
    for r, state in enumerate(chunk_states(seed, start, stop)):
        kernel(*inputs, *(out[r] for out in learned), state)
        for evaluation, log, states in zip(evaluations, logs, evaluation_states):
            copies = [out[r].copy() for out in learned]  # each evaluation starts from what the run learned
            copies[evaluation.log] = log[r]
            kernel(*evaluation.inputs, *copies, states[r])
    return start, tuple(None if isinstance(x, Scratch) else out for x, out in zip(initial, outputs))


def _array_of(x, copy: bool) -> np.ndarray:
    """The array a job fills for the initial output slice ``x`` (:func:`fill_chunk`)."""
    if isinstance(x, (Scratch, Filled)):
        return np.full(x.shape, x.value, x.dtype)
    return np.array(x) if copy else x


def run_chunk(kernel: str, inputs: tuple, seed: int, start: int, stop: int,
              initial: tuple, evaluations: tuple = ()) -> tuple[int, tuple]:
    """:func:`fill_chunk` in a worker process: ``kernel`` is the run kernel's 'module:name'. It
    fills arrays of its own: made from a Filled or Scratch, or copies of what it was sent."""
    received = tuple(replace(e, inputs=tuple(_as_sent(x) for x in e.inputs)) for e in evaluations)
    return fill_chunk(resolve_kernel(kernel), tuple(_as_sent(x) for x in inputs), seed, start, stop, initial,
                      evaluations=received)


def to_send(batches: list, jobs: list) -> list:
    """``jobs`` (:func:`glamas.parallel.batch.jobs_of`) as worker processes take them: ``(batch
    number, kernel name, inputs, seed, start, stop, initial slices, evaluations)``, each read-only
    input and each output slice of one value wrapped for transport."""
    sent = [(kernel_name(b.kernel), tuple(for_transport(x) for x in b.inputs)) for b in batches]
    evaluations = [tuple(replace(e, inputs=tuple(for_transport(x) for x in e.inputs)) for e in b.evaluations)
                   for b in batches]
    return [(k, *sent[k], batches[k].seed, start, stop, tuple(Filled.of(x) for x in first), evaluations[k])
            for k, start, stop, first in jobs]


def batch_chunk(k: int, run, *job) -> tuple[int, int, tuple]:
    """``run(*job)`` (fill_chunk or run_chunk) for batch ``k``: ``(k, start, filled outputs)``."""
    return (k, *run(*job))


@dataclass(frozen=True)
class Filled:
    """An output slice of one value in transit: its shape, type and value instead of its bytes.
    Initial outputs mostly are (Q tables filled with their initial value, zeros), and the joint
    learners' tables of four agents take hundreds of MB per job."""

    shape: tuple
    dtype: np.dtype
    value: object

    @staticmethod
    def of(x):
        """An output slice ``x`` as a Filled if every element equals the first (NaN never
        does), else ``x`` (a Scratch as it is)."""
        if isinstance(x, Scratch) or x.size == 0 or not (x == x.flat[0]).all():
            return x
        return Filled(x.shape, x.dtype, x.flat[0])


@dataclass(frozen=True)
class _ReadOnly:
    """A read-only input array in transit: transports lose the flag, and numba types a
    read-only array apart (another compilation, another cache entry)."""

    array: np.ndarray


def for_transport(x):
    return _ReadOnly(x) if isinstance(x, np.ndarray) and not x.flags.writeable else x


def _as_sent(x):
    """A copy of an input array, read-only if the caller's was."""
    if isinstance(x, _ReadOnly):
        x = np.array(x.array)
        x.flags.writeable = False
    elif isinstance(x, np.ndarray):
        x = np.array(x)
    return x


def kernel_label(kernel) -> str:
    """'module:name' of a run kernel."""
    function = getattr(kernel, "py_func", kernel)
    return f"{function.__module__}:{function.__qualname__}"


def importable(kernel) -> bool:
    """Whether another process can import ``kernel`` by its name: a module-level function of a
    module other than ``__main__``."""
    name = kernel_label(kernel)
    try:
        return not name.startswith("__main__:") and resolve_kernel(name) is kernel
    except (ImportError, AttributeError):
        return False


def kernel_name(kernel) -> str:
    """'module:name' of a module-level run kernel, which a worker process can import."""
    name = kernel_label(kernel)
    if not importable(kernel):
        raise UserError(f"the run kernel {name} is not a module-level function of an importable "
                         "module, so the Dask workers cannot load it; define it at the top level of a "
                         "module, or use the local backends")
    return name


def resolve_kernel(name: str):
    module, _, attribute = name.partition(":")
    target = importlib.import_module(module)
    for part in attribute.split("."):
        target = getattr(target, part)
    return target
