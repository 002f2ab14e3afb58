"""Independent runs in parallel: one generator state per run, threads over runs.

Batch kernels have the form ``batch(*inputs, states, *outputs)`` and loop ``prange`` over
``states``; run ``r`` reads only ``states[r]`` and writes only ``outputs[...][r]``, so the
results are the same for any number of workers and any chunking.
"""

import numba
from tqdm import tqdm  # not tqdm.auto: it warns in notebooks without ipywidgets

from glamas.rng import run_states


def set_workers(workers: int | None) -> int:
    """Use ``workers`` threads for the batch kernels (None: all cores); returns the number used."""
    available = numba.config.NUMBA_NUM_THREADS
    if workers is None:
        workers = available
    if not isinstance(workers, int) or not 1 <= workers <= available:
        raise ValueError(f"workers must be an integer from 1 to {available} (the cores numba may use), got {workers!r}")
    numba.set_num_threads(workers)
    return workers


def run_batches(batch, inputs: tuple, outputs: tuple, seed: int, *, workers: int | None = None,
                progress: str | None = None, chunk: int = 8) -> None:
    """Fill ``outputs`` (arrays whose first axis is the run) by calling ``batch`` on chunks of runs.

    ``progress`` names a progress bar (None: no bar). Chunking only serves the bar.
    """
    n_runs = outputs[0].shape[0]
    states = run_states(seed, n_runs)
    set_workers(workers)
    with tqdm(total=n_runs, desc=progress, unit="run", disable=progress is None) as bar:
        for start in range(0, n_runs, chunk):
            stop = min(start + chunk, n_runs)
            batch(*inputs, states[start:stop], *(out[start:stop] for out in outputs))
            bar.update(stop - start)
