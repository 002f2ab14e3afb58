"""A module whose record of code is pinned: a change of glamas's code form shows here."""

from dataclasses import dataclass


@dataclass
class Step:
    """One step."""
    reward: float = -10.0  # the collision penalty
    cells: tuple = ()


def shown(step: Step, width: int = 8) -> str:
    """A step as a table cell."""
    return f"{step.reward:>{width}.3f}" + f"{'-' if not step.cells else len(step.cells)!r:{width}}"


def total(values, *, start=0.0):
    for value in values:
        start += value
    return start if start else None
