"""Every learner by name. An experiment finds its learners here and knows nothing else of them:
adding a learner is one module that declares a :class:`glamas.learners.spec.Learner` and one
:func:`register` call (below for the library's own, in a test or a notebook for others). A
registered learner of family 'other' can then be trained beside the chapter's learners
(:mod:`glamas.experiments.related_work`) and in the scaling study by its name.

Seeds: each learner's runs draw from a master seed of its own (:func:`master_seed`). The chapter's
and the related-work learners keep the seeds of the committed results; another learner's seed
comes from its name, so registering it changes nobody else's.
"""

import zlib

from glamas.errors import UserError
from glamas.learners import cq, independent, joint_state, mmdp, sparse_maq, two_observe
from glamas.learners.spec import Learner

LEARNERS: dict[str, Learner] = {}
"""The registered learners by name, in the order they were registered."""
SEED_OFFSETS = {"chapter": 0, "related": 2 ** 32, "other": 2 ** 33}
"""Where each family's master seeds start (:func:`master_seed`): apart from each other for every
experiment seed below 2**24."""
NAME_SLOTS = 2 ** 20
"""Seed slots of the family 'other': a learner's slot comes from its name."""


def register(learner: Learner) -> Learner:
    """Make ``learner`` known by its name (a name registered again is replaced)."""
    if learner.family not in SEED_OFFSETS:
        raise UserError(f"a learner's family must be one of {sorted(SEED_OFFSETS)}, got {learner.family!r}")
    taken = {_slot(other.name): other.name for other in LEARNERS.values()
             if other.family == "other" and other.name != learner.name}
    if learner.family == "other" and _slot(learner.name) in taken:
        raise UserError(f"learner {learner.name!r} would draw the seeds of {taken[_slot(learner.name)]!r}; "
                         "choose another name")
    LEARNERS[learner.name] = learner
    return learner


def unregister(name: str) -> None:
    """Forget learner ``name`` (a learner registered for a while, as in a test)."""
    LEARNERS.pop(name, None)


def get(name: str) -> Learner:
    """The learner registered as ``name``."""
    if name not in LEARNERS:
        raise UserError(f"no learner {name!r}; the learners are {', '.join(LEARNERS)}")
    return LEARNERS[name]


def label(name: str) -> str:
    """How figures and tables call learner ``name``."""
    return get(name).label


def family(name: str) -> tuple:
    """The names of the learners of family ``name`` ('chapter', 'related' or 'other'), in
    registration order."""
    return tuple(learner.name for learner in LEARNERS.values() if learner.family == name)


def beyond_the_chapter() -> tuple:
    """The names of every registered learner that is not the chapter's, in registration order:
    the related-work learners first."""
    return tuple(learner.name for learner in LEARNERS.values() if learner.family != "chapter")


def master_seed(key: int, members: tuple, name: str, family: str = "chapter") -> int:
    """The master seed of the runs of ``name`` for the seed key ``key`` (the experiment's seed, or
    a number made from it). In the families 'chapter' and 'related', ``name`` is one of
    ``members`` (what the experiment can train of that family, in a fixed order) and the seed is
    the family's offset + key * len(members) + its place in members; in the family 'other' it is
    the offset + key * NAME_SLOTS + the slot of its name. Distinct for every (key, name), and the
    same whichever other learners are trained or registered."""
    if family == "other":
        return SEED_OFFSETS[family] + key * NAME_SLOTS + _slot(name)
    return SEED_OFFSETS[family] + key * len(members) + members.index(name)


def _slot(name: str) -> int:
    return zlib.crc32(name.encode()) % NAME_SLOTS


for _learner in (independent.LEARNER, joint_state.LEARNER, mmdp.LEARNER, two_observe.LEARNER,
                 sparse_maq.LEARNER, cq.LEARNER):
    register(_learner)
