"""Every learner by name. An experiment finds its learners here and knows nothing else of them:
adding a learner is one module that declares a :class:`glamas.learners.spec.Learner` and calls
:func:`register` on it. The modules of :mod:`glamas.learners` are found here (:func:`discover`,
which the package runs when it is first imported, before any of its modules is used), so a module
placed there is known by being there, as an experiment of :mod:`glamas.experiments` is. A learner
defined elsewhere (a user's module, a test, a notebook) is known once its :func:`register` has run,
and a module of one's own is imported with the package's when the environment variable
GLAMAS_LEARNERS names it (:data:`LEARNER_MODULES`). A registered learner can then be trained by name
in every experiment that trains learners, with settings of its own (its spec's ``defaults``) that
configs hold by its name.

Seeds: each learner's runs draw from a master seed of its own (:func:`master_seed`), made from the
experiment's seed key, its family and the seed slot its spec declares, so that the order in which
learners are registered or listed never decides anyone's streams.
"""

import importlib
import os
import pkgutil
import sys
import zlib

from glamas.errors import UserError
from glamas.learners.spec import Learner

LEARNERS: dict[str, Learner] = {}
"""The registered learners by name."""
SEED_OFFSETS = {"chapter": 0, "related": 2 ** 32, "other": 2 ** 33}
"""Where each family's master seeds start (:func:`master_seed`): apart from each other for every
experiment seed below 2**24 (the command line's largest, :data:`glamas.cli.MAX_SEED`)."""
SEED_STRIDES = {"chapter": 4, "related": 2}
"""Seed slots per seed key in each family (:func:`master_seed`): the chapter's four learners
(slots 0-3) and the two related-work learners (0-1). The studies beyond the chapter name their
seeds instead (:func:`glamas.seeds.named`)."""
NAME_SLOTS = 2 ** 20
"""Seed slots of the learners that draw from their name (family 'other', or a slot beyond the
experiment's stride)."""
FAMILIES = ("chapter", "related", "other")


def _module(learner: Learner) -> str:
    """The module that defines ``learner``'s kernel."""
    return getattr(learner.kernel, "__module__", "?")


def register(learner: Learner) -> Learner:
    """Make ``learner`` known by its name. A learner of the same name from another module (its
    kernel's) is refused; the same module registering it again (a reload) replaces it."""
    known = LEARNERS.get(learner.name)
    if known is not None and _module(known) != _module(learner):
        raise UserError(f"a learner named {learner.name!r} is registered already (by {_module(known)}); "
                        f"{_module(learner)} must choose another name")
    if learner.family not in FAMILIES:
        raise UserError(f"a learner's family must be one of {FAMILIES}, got {learner.family!r}")
    if learner.family != "other" and not (isinstance(learner.seed_slot, int) and learner.seed_slot >= 0):
        raise UserError(f"learner {learner.name!r} of family {learner.family!r} must declare its seed_slot, "
                         "a whole number >= 0")
    taken = {_name_slot(other.name): other.name for other in LEARNERS.values()
             if other.family == "other" and other.name != learner.name}
    if learner.family == "other" and _name_slot(learner.name) in taken:
        raise UserError(f"learner {learner.name!r} would draw the seeds of {taken[_name_slot(learner.name)]!r}; "
                         "choose another name")
    LEARNERS[learner.name] = learner
    ordered = sorted(LEARNERS.values(), key=_order)
    LEARNERS.clear()
    LEARNERS.update((other.name, other) for other in ordered)
    return learner


def _order(learner: Learner) -> tuple:
    """Where a learner stands in LEARNERS, whatever the order the modules were imported in: by
    family, then seed slot, then name."""
    slot = learner.seed_slot if learner.seed_slot is not None else NAME_SLOTS
    return FAMILIES.index(learner.family), slot, learner.name


LEARNER_MODULES = "GLAMAS_LEARNERS"
"""The environment variable naming modules of learners outside the package (comma-separated, e.g.
``GLAMAS_LEARNERS=my_learners``, importable from ``PYTHONPATH``), which :func:`discover` imports too:
so a figure script trains a learner of one's own by name (``--learners my_learner``)."""


def discover() -> None:
    """Import every module of :mod:`glamas.learners`, and those :data:`LEARNER_MODULES` names: each
    registers the learners it declares. A module named there that cannot be imported is one warning
    line naming it (its learners are then unknown, and a config naming them says so)."""
    package = importlib.import_module("glamas.learners")
    for module in pkgutil.iter_modules(package.__path__, f"{package.__name__}."):
        if module.name != __name__:
            importlib.import_module(module.name)
    for name in (name.strip() for name in os.environ.get(LEARNER_MODULES, "").split(",")):
        try:
            if name:
                importlib.import_module(name)
        except ImportError as error:
            print(f"warning: {LEARNER_MODULES} names the module {name!r}, which cannot be imported ({error}); put "
                  "its directory on PYTHONPATH or correct the name", file=sys.stderr)


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
    """The names of the learners of family ``name`` ('chapter', 'related' or 'other'), by seed
    slot (then name)."""
    members = [learner for learner in LEARNERS.values() if learner.family == name]
    return tuple(learner.name for learner in sorted(members, key=lambda x: (x.seed_slot or 0, x.name)))


def master_seed(key: int, name: str, strides: dict = SEED_STRIDES) -> int:
    """The master seed of the runs of learner ``name`` for the seed key ``key`` (the experiment's
    seed, or a number made from it): its family's offset + key * the family's stride + its
    declared seed slot. A learner of family 'other', or whose slot is not below its family's stride
    in ``strides``, draws from a slot made from its name instead (the offset of 'other' + key *
    NAME_SLOTS + that slot). Distinct for every (key, learner), and the same whichever other
    learners are registered, listed or trained."""
    learner = get(name)
    stride = strides.get(learner.family, 0)
    if learner.family != "other" and learner.seed_slot < stride:
        return SEED_OFFSETS[learner.family] + key * stride + learner.seed_slot
    return SEED_OFFSETS["other"] + key * NAME_SLOTS + _name_slot(name)


def _name_slot(name: str) -> int:
    return zlib.crc32(name.encode()) % NAME_SLOTS

