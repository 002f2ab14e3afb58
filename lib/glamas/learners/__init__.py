"""The learners, one module each: each holds its compiled run kernel and how its inputs are made.

Section 4's line-world agents (:mod:`~glamas.learners.single_gla`, one GLA per agent;
:mod:`~glamas.learners.and_network`, an AND network of GLAs per agent), and the gridworld learners
of Section 5.3 and of the related work, each declared as a :class:`glamas.learners.spec.Learner`
and registered by name by its own module (:mod:`glamas.learners.registry`): independent Q-learners,
joint-state learners, the MMDP learner, 2observe (Alg. 4), sparse tabular MAQ and CQ-learning.
Importing the package imports every module of it, so that every learner is registered before any
is asked for; a module added here is found the same way.
"""

from glamas.learners import registry as _registry

_registry.discover()
