"""Every registered learner keeps the learner contract (glamas.learners.contract), and the check
fails on a learner that breaks a promise."""

from dataclasses import replace

import pytest
from numba import njit

from glamas.learners import contract, independent, registry, two_observe


@pytest.mark.parametrize("name", list(registry.LEARNERS))
def test_every_registered_learner_keeps_the_contract(name):
    contract.check(registry.get(name))


@pytest.mark.parametrize("broken, promise", [
    (replace(two_observe.LEARNER, freeze=lambda inputs: inputs), "it changes what it learned"),
    (replace(independent.LEARNER, table_shape=lambda cells, agents: (agents, cells, 5)), "4 or 4\\*\\*2 actions"),
    (replace(independent.LEARNER, table_shape=lambda cells, agents: (agents, cells)), "three whole numbers"),
    (replace(independent.LEARNER, kernel=njit(independent.run.py_func)), "cache=True and nogil=True"),
    (replace(independent.LEARNER, kernel=njit(nogil=True)(independent.run.py_func)), "cache=True and nogil=True"),
    (replace(independent.LEARNER, label=""), "name and label must be non-empty"),
])
def test_a_broken_promise_is_named(broken, promise):
    with pytest.raises(contract.ContractError, match=f"learner '{broken.name}' breaks its contract: .*{promise}"):
        contract.check(broken, maps=("tunnel_to_goal",), runs=2, episodes=5)


def test_what_is_not_a_learner_is_refused():
    with pytest.raises(contract.ContractError, match="a learner is a glamas.learners.spec.Learner, got dict"):
        contract.check({"name": "x"})
