"""The outputs of batches run before, kept to fill an identical batch with instead of running it.

A process may keep the outputs of the batches it runs (:func:`reuse_batches`): the runs are
deterministic, so a later batch with the same kernel, master seed, inputs and initial outputs
takes them instead of running again. glamas.reproduce does so, running every figure script in
one process: the 2observe of Fig. 11 is the default reading of the Fig. 10 study, and the
related-work comparison trains the chapter's learners as Fig. 11 does.
"""

import collections
import hashlib

import numpy as np

from glamas.errors import UserError
from glamas.parallel.batch import Batch, Scratch

MEMO_BYTES = 0
"""Most bytes of outputs that this process keeps of the batches it has run, to fill an identical
batch with instead of running it (:func:`recall`); 0, the default, keeps none
(:func:`reuse_batches` sets it)."""
_kept = collections.OrderedDict()  # batch key -> copies of its filled outputs, least recently used first


def reuse_batches(max_bytes: int) -> None:
    """From now on keep up to ``max_bytes`` of the outputs of the batches this process runs, and
    fill a batch identical to one of them from them instead of running it (0: keep none, the
    default). glamas.reproduce does, running every figure script in one process."""
    global MEMO_BYTES
    if isinstance(max_bytes, bool) or not isinstance(max_bytes, int) or max_bytes < 0:
        raise UserError(f"max_bytes must be a whole number >= 0, got {max_bytes!r}")
    MEMO_BYTES = max_bytes
    while _kept and _kept_bytes() > MEMO_BYTES:
        _kept.popitem(last=False)


def _kept_bytes() -> int:
    return sum(out.nbytes for outputs in _kept.values() for out in outputs)


def key_of(batch: Batch):
    """What makes a batch's outputs what they are: its kernel, and a digest of its master seed,
    inputs and initial outputs (the runs are deterministic); None for a batch with a Scratch
    output, whose outputs take more than an eighth of MEMO_BYTES, or whose inputs hold something
    other than arrays, numbers, strings and tuples of them."""
    if any(isinstance(out, Scratch) for out in batch.outputs):
        return None
    if sum(out.nbytes for out in batch.outputs) > MEMO_BYTES // 8:
        return None
    digest = hashlib.blake2b(digest_size=20)
    if not _digest(digest, (batch.seed, batch.inputs, batch.outputs, tuple(e.key() for e in batch.evaluations))):
        return None
    return batch.kernel, digest.hexdigest()


def _digest(digest, x) -> bool:
    """Feed ``x`` to ``digest``; False where it holds something else than :func:`key_of` takes."""
    if isinstance(x, np.ndarray):
        digest.update(f"array {x.dtype.str} {x.shape}:".encode())
        digest.update(np.ascontiguousarray(x).tobytes())
        return True
    if isinstance(x, tuple):
        digest.update(f"{type(x).__qualname__} {len(x)}(".encode())
        if not all(_digest(digest, item) for item in x):
            return False
        digest.update(b")")
        return True
    if x is None or isinstance(x, (bool, int, float, str, np.generic)):
        digest.update(f"{type(x).__qualname__} {x!r};".encode())
        return True
    return False


def recall(key, batch: Batch) -> bool:
    """Fill ``batch``'s outputs from the batch of the same ``key`` that this process ran before
    (a figure script drawing what another one has trained, as glamas.reproduce runs them all);
    False if there is none."""
    if key is None or key not in _kept:
        return False
    _kept.move_to_end(key)
    for out, kept in zip(batch.outputs, _kept[key]):
        out[...] = kept
    return True


def remember(key, batch: Batch) -> None:
    """Keep copies of ``batch``'s filled outputs under ``key``, forgetting the least recently
    used batches beyond MEMO_BYTES."""
    if key is None:
        return
    _kept[key] = tuple(out.copy() for out in batch.outputs)
    while _kept_bytes() > MEMO_BYTES:
        _kept.popitem(last=False)
