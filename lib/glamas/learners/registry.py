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

Seeds: each experiment names the master seed of a learner's runs by the master seed, the
experiment, its case and the learner's name (:func:`glamas.seeds.named`), so that the order in
which learners are registered or listed never decides anyone's streams.
"""

import importlib
import os
import pkgutil
import sys

from glamas.errors import UserError
from glamas.learners.spec import Learner

LEARNERS: dict[str, Learner] = {}
"""The registered learners by name."""
FAMILIES = ("chapter", "related", "other")
"""Where a learner comes from: the chapter's, the related work's, or another's."""


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
    if learner.rank is not None and not (isinstance(learner.rank, int) and learner.rank >= 0):
        raise UserError(f"learner {learner.name!r}: its rank must be a whole number >= 0 or None, got {learner.rank!r}")
    LEARNERS[learner.name] = learner
    ordered = sorted(LEARNERS.values(), key=_order)
    LEARNERS.clear()
    LEARNERS.update((other.name, other) for other in ordered)
    return learner


def _order(learner: Learner) -> tuple:
    """Where a learner stands in LEARNERS, whatever the order the modules were imported in: by
    family, then rank (the unranked after), then name."""
    return FAMILIES.index(learner.family), learner.rank is None, learner.rank or 0, learner.name


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
    for name in filter(None, (name.strip() for name in os.environ.get(LEARNER_MODULES, "").split(","))):
        import_own(name)


def import_own(name: str) -> None:
    """Import the module of one's own ``name`` (:data:`LEARNER_MODULES`); whatever its import raises
    (it cannot be found, has a syntax error, raises, exits, registers a taken name) is one warning
    line naming the module and the fault: its learners are then unknown, and a config naming them
    says so."""
    try:
        importlib.import_module(name)
    except ImportError as error:
        _warn(name, f"which cannot be imported ({error}); put its directory on PYTHONPATH or correct the name")
    except SyntaxError as error:
        _warn(name, f"which has a syntax error ({error.msg}, {error.filename} line {error.lineno}); correct it")
    # a user's module may raise anything on import; a SystemExit let through would end the figure script
    # there, saying nothing
    except (Exception, SystemExit, KeyboardInterrupt) as error:
        reason = " ".join((str(error) or type(error).__name__).split())
        _warn(name, f"which fails on import ({type(error).__name__}: {reason}); correct it")


def _warn(name: str, what: str) -> None:
    print(f"warning: {LEARNER_MODULES} names the module {name!r}, {what}; its learners are unknown", file=sys.stderr)


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
    """The names of the learners of family ``name`` ('chapter', 'related' or 'other'), in the
    order of LEARNERS (by rank, then name)."""
    return tuple(learner.name for learner in LEARNERS.values() if learner.family == name)
