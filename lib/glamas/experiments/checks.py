"""Checks shared by the experiments' config dataclasses; each error names the field and its bound."""

import numpy as np


def whole_numbers(config, minimums: dict) -> None:
    """Raise unless each field named in ``minimums`` is a whole number (not a bool) >= its minimum."""
    for name, minimum in minimums.items():
        value = getattr(config, name)
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
            raise ValueError(f"{name} must be a whole number >= {minimum}, got {value!r}")
