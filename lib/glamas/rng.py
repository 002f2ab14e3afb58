"""Per-run random streams for the compiled kernels.

Every run owns a xoshiro256** state (four uint64 words) seeded from its own
``numpy.random.SeedSequence`` child. A kernel only ever touches its own run's
state, so results do not depend on how many workers execute the runs. The draws are inlined into
the kernels: ``uniform`` and ``integer`` by numba (``inline="always"``), the generator's step
``next_u64`` by LLVM, which costs compile time once instead of at every draw of every kernel
(:mod:`glamas.learners.episode`).
"""

import numpy as np
from numba import njit

from glamas.errors import UserError

_U64 = np.uint64
_TO_UNIT = 1.0 / 9007199254740992.0  # 2**-53: turns 53 random bits into [0, 1)


def check_seed(seed) -> None:
    """Reject a seed that is not a non-negative integer."""
    if not isinstance(seed, (int, np.integer)) or seed < 0:
        raise UserError(f"seed must be a non-negative integer, got {seed!r}")


def run_states(seed: int, n_runs: int) -> np.ndarray:
    """One generator state per run, shape (n_runs, 4), from ``SeedSequence(seed).spawn``."""
    check_seed(seed)
    if not isinstance(n_runs, (int, np.integer)) or n_runs < 1:
        raise UserError(f"n_runs must be a positive integer, got {n_runs!r}")
    children = np.random.SeedSequence(int(seed)).spawn(int(n_runs))
    return np.stack([child.generate_state(4, np.uint64) for child in children])


def chunk_states(seed: int, start: int, stop: int) -> np.ndarray:
    """The states of runs ``start`` to ``stop - 1``: equal to ``run_states(seed, n)[start:stop]``
    for any ``n >= stop``, without spawning the runs before ``start``.

    Child r of ``SeedSequence(seed).spawn`` is ``SeedSequence(seed, spawn_key=(r,))``, so a job
    given only its run indices draws the same streams as the whole sweep.
    """
    check_seed(seed)
    if not (isinstance(start, (int, np.integer)) and isinstance(stop, (int, np.integer)) and 0 <= start < stop):
        raise UserError(f"runs must be whole numbers with 0 <= start < stop, got start={start!r}, stop={stop!r}")
    return np.stack([np.random.SeedSequence(int(seed), spawn_key=(int(r),)).generate_state(4, np.uint64)
                     for r in range(start, stop)])


@njit(cache=True, inline="always")
def _rotl(x, k):
    return (x << _U64(k)) | (x >> _U64(64 - k))


@njit(cache=True)  # inlined by LLVM (module docstring)
def next_u64(state):
    """xoshiro256** (Blackman and Vigna): advance ``state`` in place, return 64 bits."""
    result = _rotl(state[1] * _U64(5), 7) * _U64(9)
    t = state[1] << _U64(17)
    state[2] ^= state[0]
    state[3] ^= state[1]
    state[1] ^= state[2]
    state[0] ^= state[3]
    state[2] ^= t
    state[3] = _rotl(state[3], 45)
    return result


@njit(cache=True, inline="always")
def uniform(state):
    """A float in [0, 1)."""
    return float(next_u64(state) >> _U64(11)) * _TO_UNIT


@njit(cache=True, inline="always")
def integer(state, n):
    """An integer in [0, n), n >= 1."""
    return min(int(uniform(state) * n), n - 1)


@njit(cache=True, inline="always")
def categorical(state, probs):
    """An index drawn with the given probabilities (which sum to one)."""
    return _first_above(probs, uniform(state))


@njit(cache=True, inline="always")
def _first_above(probs, r):
    """The first index whose cumulative probability exceeds r (the last index if none does)."""
    acc = 0.0
    for i in range(probs.shape[0] - 1):
        acc += probs[i]
        if r < acc:
            return i
    return probs.shape[0] - 1


@njit(cache=True)
def reseed(state, stream):
    """Replace ``state`` in place by a new one drawn from it and the number ``stream`` with
    splitmix64, the seeding xoshiro's authors recommend: from one state, another stream number
    gives an unrelated stream (a run that keeps its initial draws and continues on another)."""
    x = next_u64(state) ^ (_U64(stream) * _U64(0x9E3779B97F4A7C15))
    for i in range(4):
        x += _U64(0x9E3779B97F4A7C15)
        z = (x ^ (x >> _U64(30))) * _U64(0xBF58476D1CE4E5B9)
        z = (z ^ (z >> _U64(27))) * _U64(0x94D049BB133111EB)
        state[i] = z ^ (z >> _U64(31))
