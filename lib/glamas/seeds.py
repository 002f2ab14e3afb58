"""Master seeds named by what they seed.

A study that trains its learners on many cases (numbers of agents, maps, instances) gives each
(learner, case) a master seed of its own. A key made by arithmetic on the case collides as soon
as one term outgrows the room left for it (``16 seed + N`` gives seed 1 with one agent the
streams of seed 0 with 17). Here the names are the entropy of a ``numpy.random.SeedSequence``,
which hashes its words together instead of adding them, so two cases share streams only if two of
their names collide (strings are named by their CRC-32; a test enumerates each study's grid). Every
name is one 32-bit word, so that two lists of names are two lists of words (a larger integer would
be split into several words and could spell another list).
"""

import zlib

import numpy as np

from glamas.errors import UserError


def named(*names: int | str) -> int:
    """The master seed named by ``names`` (integers in [0, 2**32) as they are, strings by their
    CRC-32, in order): 48 bits drawn from ``numpy.random.SeedSequence(names)``, so that every
    training seed stays below the evaluations' (:data:`glamas.training.EVALUATION_SEEDS`).

    The last name must be a string (the study's or the learner's): SeedSequence pads its entropy
    with zeros, so two lists of names that differ only by trailing zeros (``(7,)`` and ``(7, 0)``)
    would name one seed; a list ending in a name cannot be another's with zeros added."""
    if not names or not isinstance(names[-1], str):
        raise UserError(f"a seed's names must end with a string (the study's or the learner's name), got {names!r}")
    entropy = [zlib.crc32(name.encode()) if isinstance(name, str) else name for name in names]
    if not all(isinstance(word, (int, np.integer)) and not isinstance(word, bool) and 0 <= word < 2 ** 32
               for word in entropy):
        raise UserError(f"a seed is named by integers in [0, 2**32) and strings, got {names!r}")
    return int(np.random.SeedSequence([int(word) for word in entropy]).generate_state(1, np.uint64)[0] >> np.uint64(16))
