"""Joint states (all agents' cells) and joint actions as mixed-radix numbers, agent 0 most
significant: the one encoding shared by the joint learners and dynamic programming."""

from numba import njit


@njit(cache=True, inline="always")
def joint_index(digits, base):
    """The number whose base-``base`` digits are ``digits`` (e.g. the agents' cells)."""
    number = 0
    for i in range(digits.shape[0]):
        number = number * base + digits[i]
    return number


@njit(cache=True, inline="always")
def split_index(number, base, out):
    """Write ``number``'s base-``base`` digits into ``out``: the inverse of :func:`joint_index`."""
    for i in range(out.shape[0] - 1, -1, -1):
        out[i] = number % base
        number //= base
