"""Checks shared by the experiments' config dataclasses; each error names the field and its bound."""

import dataclasses
import math
import numbers
import types
import typing

import numpy as np

from glamas.errors import UserError

MAX_COUNT = 2 ** 31 - 1
"""Largest whole-number setting: counts stay far from the kernels' 64-bit integer range (the
kernels multiply counts such as iterations by points)."""


def whole_numbers(config, minimums: dict) -> None:
    """Raise unless each field named in ``minimums`` is a whole number (not a bool) from its
    minimum to MAX_COUNT."""
    for name, minimum in minimums.items():
        value = getattr(config, name)
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
            raise UserError(f"{name} must be a whole number >= {minimum}, got {value!r}")
        if value > MAX_COUNT:
            raise UserError(f"{name} must be at most {MAX_COUNT}, got {value!r}")


def in_unit_interval(config, name: str) -> None:
    """Raise unless field ``name`` of ``config`` is a number in (0, 1] (a rate or a probability)."""
    value = getattr(config, name)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 < value <= 1:
        raise UserError(f"{name} must be a number in (0, 1], got {value!r}")


def distinct_names(config, name: str, known, what: str) -> None:
    """Raise unless field ``name`` of ``config`` is a non-empty tuple or list of distinct names
    among ``known`` (``what`` says what they are, e.g. 'registered learners'); store it as a tuple."""
    value = getattr(config, name)
    names = tuple(value) if isinstance(value, (tuple, list)) else ()
    if not names or len(set(names)) != len(names) or not set(names) <= set(known):
        raise UserError(f"{name} must be distinct names of {what} ({', '.join(known)}), got {value!r}")
    object.__setattr__(config, name, names)


def agent_counts(config, minimum: int) -> None:
    """Raise unless ``config.agents`` is a non-empty tuple or list of distinct whole numbers of agents
    of at least ``minimum``; store them as a sorted tuple."""
    agents = tuple(config.agents) if isinstance(config.agents, (tuple, list)) else ()
    if not agents or len(set(agents)) != len(agents) or not all(
            isinstance(n, int) and not isinstance(n, bool) and n >= minimum for n in agents):
        raise UserError(f"agents must be distinct whole numbers >= {minimum}, got {config.agents!r}")
    object.__setattr__(config, "agents", tuple(sorted(agents)))


def one_of(config, name: str, allowed) -> None:
    """Raise unless field ``name`` of ``config`` is one of ``allowed``."""
    value = getattr(config, name)
    if value not in allowed:
        raise UserError(f"{name} must be one of {sorted(allowed)}, got {value!r}")


def positive(config, name: str) -> None:
    """Raise unless field ``name`` of ``config`` is a number > 0 (a budget, a scale)."""
    value = getattr(config, name)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0:
        raise UserError(f"{name} must be a number > 0, got {value!r}")


def field_types(config) -> None:
    """Raise UserError naming the field unless every field of a config dataclass has its
    annotated type: int and float a real number (float: finite; whether an int field is whole and
    in range is the config's own check), str a string, a dataclass an instance of it (``X | None``
    also None).

    Called first in a config's ``__post_init__``, so that a string for a number or None for a
    map gets this message instead of a TypeError deep inside the checks that follow."""
    hints = typing.get_type_hints(type(config))
    for field in dataclasses.fields(config):
        value = getattr(config, field.name)
        problem = _type_problem(hints.get(field.name), value)
        if problem:
            raise UserError(f"{type(config).__name__}.{field.name} must be {problem}, got {value!r}")


def _type_problem(hint, value) -> str | None:
    """What ``value`` must be to have type ``hint`` (None: it has it, or the hint is not checked)."""
    if isinstance(hint, types.UnionType) or typing.get_origin(hint) is typing.Union:
        options = typing.get_args(hint)
        if value is None and type(None) in options:
            return None
        hint = next((option for option in options if option is not type(None)), None)
    real = isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))
    if hint is int:
        return None if real else "a whole number"
    if hint is float:
        return None if real and math.isfinite(value) else "a finite number"
    if hint is str:
        return None if isinstance(value, str) else "a string"
    if dataclasses.is_dataclass(hint):
        return None if isinstance(value, hint) else f"a {hint.__name__}"
    return None


def suspect_settings(config, limit: int = 3) -> str:
    """The real-valued settings of ``config`` furthest (in orders of magnitude) from their
    defaults, as 'name=value (default d)': the likely cause when the learning leaves the range
    of finite numbers. Empty if none differs."""
    ranked = sorted(_changed_reals(config), key=lambda row: -row[0])
    return ", ".join(f"{name}={value!r} (default {default!r})" for _, name, value, default in ranked[:limit])


def _changed_reals(config, prefix: str = "") -> list[tuple]:
    default = type(config)()
    hints = typing.get_type_hints(type(config))
    rows = []
    for field in dataclasses.fields(config):
        value, initial = getattr(config, field.name), getattr(default, field.name)
        if dataclasses.is_dataclass(value):
            rows += _changed_reals(value, f"{prefix}{field.name}.")
        elif hints.get(field.name) is float and value != initial:
            distance = abs(math.log10(abs(value) + 1e-300) - math.log10(abs(initial) + 1e-300))
            rows.append((distance, f"{prefix}{field.name}", value, initial))
    return rows
