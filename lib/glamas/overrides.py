"""Settings from the command line (the figure scripts' --learners and --set): any field of an
experiment's configuration, of a dataclass inside it (``q.learning_rate``, ``rewards.goal``) or of a
learner's own settings by the learner's name (``two_observe.gla_learning_rate``), as CleanRL makes
every hyperparameter a flag of its typed dataclass.

A value is read as the type of the field's current value (a whole number, a number, true/false, a
text, or comma-separated items for a tuple) and checked by the dataclass itself when it is
replaced, so every bound a configuration checks holds for the command line too. A bad name or
value is a UserError of one line that names the setting and what it takes.
"""

import dataclasses
import math

from glamas.errors import UserError

_TRUE, _FALSE = ("true", "yes", "1"), ("false", "no", "0")
OWN_OPTIONS = ("runs", "iterations", "episodes")
"""Settings a figure script sets with an option of its own (``--runs``, ``--episodes``): its --set
refuses them (:func:`check_not_own`), so that the two cannot disagree."""


def with_learners(config, names: str):
    """``config`` training the learners ``names`` (comma-separated registered names): its field
    ``learners``, or that of the one configuration inside it that has one (the crowd's ``study``)."""
    chosen = tuple(name.strip() for name in names.split(",") if name.strip())
    if _has_field(config, "learners"):
        return _replaced(config, "learners", chosen, f"--learners {names}")
    inside = [f.name for f in dataclasses.fields(config) if _has_field(getattr(config, f.name), "learners")]
    if len(inside) != 1:
        raise UserError(f"--learners: this experiment's configuration ({type(config).__name__}) trains no "
                        "choice of learners")
    return _replaced(config, inside[0], with_learners(getattr(config, inside[0]), names), f"--learners {names}")


def with_setting(config, assignment: str):
    """``config`` with the setting of ``assignment``, ``PATH=VALUE`` (PATH: a field, or names joined
    by dots down to one, a learner's settings by the learner's name)."""
    path, equals, text = assignment.partition("=")
    if not equals or not path:
        example = next((entry for entry in settable(config) if "." in entry), "max_steps=100")
        raise UserError(f"--set {assignment}: expected NAME.FIELD=VALUE, e.g. --set {example} (--help lists them)")
    return _set(config, path.split("."), text, f"--set {assignment}")


def check_not_own(assignment: str) -> None:
    """Refuse a command line's ``--set`` of a setting that has an option of its own (OWN_OPTIONS)."""
    path, _, text = assignment.partition("=")
    if path in OWN_OPTIONS:
        raise UserError(f"--set {assignment}: {path} has an option of its own, which would disagree with it: "
                        f"give --{path} {text} instead")


def settable(config) -> list[str]:
    """Every setting --set reaches in ``config``, as ``PATH=CURRENT`` (the --help's list)."""
    return [f"{path}={_shown(value)}" for path, value in _leaves(config, "")]


def _set(node, names: list, text: str, where: str):
    head, rest = names[0], names[1:]
    if isinstance(node, dict):
        if head not in node:
            raise UserError(f"{where}: no learner {head!r} with settings here; those with settings: "
                            f"{', '.join(sorted(node)) or 'none'}")
        return {**node, head: _set(node[head], rest, text, where)} if rest else _unsettable(where)
    if not dataclasses.is_dataclass(node):
        return _unsettable(where)
    if not _has_field(node, head):
        child = getattr(node, "settings", None)
        if isinstance(child, dict) and head in child:  # a learner's settings by its name
            return _replaced(node, "settings", _set(child, names, text, where), where)
        fields = [f.name for f in dataclasses.fields(node)] + sorted(child or ())
        if isinstance(child, dict) and _is_learner(head) and _has_field(node, "learners"):
            trained = ",".join(node.learners)
            raise UserError(f"{where}: the learner {head!r} is not trained here ({trained}); train it too with "
                            f"--learners {trained},{head}")
        raise UserError(f"{where}: {type(node).__name__} has no setting {head!r}; it has {', '.join(fields)}")
    current = getattr(node, head)
    if not rest and (dataclasses.is_dataclass(current) or isinstance(current, dict)):
        return _unsettable(where)
    annotation = str(next(f.type for f in dataclasses.fields(node) if f.name == head))
    value = _set(current, rest, text, where) if rest else _parsed(current, text, where, annotation)
    return _replaced(node, head, value, where)


def _replaced(node, name: str, value, where: str):
    try:
        return dataclasses.replace(node, **{name: value})
    except (ValueError, TypeError) as error:
        raise UserError(f"{where}: {str(error).splitlines()[0]}") from None


def _parsed(current, text: str, where: str, annotation: str = ""):
    """``text`` as a value of ``current``'s type; for a field that may be None (its ``annotation``
    says so, ``float | None``), 'none' or a value of the type it names beside None."""
    kind = type(current)
    if text.lower() == "none" and (current is None or "None" in annotation):
        return None
    if current is None:
        for name, example in (("bool", False), ("int", 0), ("float", 0.0), ("str", "")):
            if name in annotation.replace("None", ""):
                return _parsed(example, text, where)
    try:
        if isinstance(current, bool):
            if text.lower() not in _TRUE + _FALSE:
                raise ValueError
            return text.lower() in _TRUE
        if isinstance(current, int):
            return int(text)
        if isinstance(current, float):
            value = float(text)
            if not math.isfinite(value):
                raise ValueError
            return value
        if isinstance(current, str):
            return text
        if isinstance(current, tuple) and current:
            return tuple(_parsed(current[0], item.strip(), where) for item in text.split(","))
    except ValueError:
        raise UserError(f"{where}: expected {_kind_name(current)}, got {text!r}") from None
    raise UserError(f"{where}: a setting of type {kind.__name__} cannot be given on the command line")


def _kind_name(current) -> str:
    if isinstance(current, bool):
        return "true or false"
    if isinstance(current, tuple):
        return f"comma-separated items, each {_kind_name(current[0])}"
    return {int: "a whole number", float: "a finite number", str: "a text"}.get(type(current), type(current).__name__)


def _unsettable(where: str):
    raise UserError(f"{where}: that names a group of settings, not one; add .FIELD (the --help lists them)")


def _leaves(node, prefix: str):
    """(path, value) of every field --set can reach below ``node``."""
    if isinstance(node, dict):
        for name, child in node.items():
            yield from _leaves(child, f"{prefix}{name}.")
        return
    for f in dataclasses.fields(node):
        value = getattr(node, f.name)
        if dataclasses.is_dataclass(value) or (f.name == "settings" and isinstance(value, dict)):
            yield from _leaves(value, prefix if f.name == "settings" else f"{prefix}{f.name}.")
        elif value is None or isinstance(value, (bool, int, float, str)) or (
                isinstance(value, tuple) and value and isinstance(value[0], (int, float, str))):
            yield f"{prefix}{f.name}", value


def _is_learner(name: str) -> bool:
    from glamas.learners import registry  # the registry imports every learner: only when asked

    return name in registry.LEARNERS


def _has_field(node, name: str) -> bool:
    return dataclasses.is_dataclass(node) and name in {f.name for f in dataclasses.fields(node)}


def _shown(value) -> str:
    return ",".join(map(str, value)) if isinstance(value, tuple) else str(value).lower() \
        if isinstance(value, bool) else str(value)
