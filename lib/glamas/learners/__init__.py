"""The gridworld learners of the chapter's Section 5.3, each a compiled episode loop over the
shared gridworld rules: independent Q-learners, joint-state learners, the MMDP learner and 2observe
(Alg. 4)."""
