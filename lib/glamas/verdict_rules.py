"""The rule book of docs/verdicts.md as data: for each kind of sentence, the metrics of its family
and the measurement choices it leaves open. A claim names its rule (``data/chapter/*.json``); its
verdict is judged at every value of its rule's choices (:func:`glamas.claims.verdicts`)."""

import re
from dataclasses import dataclass


@dataclass(frozen=True)
class Choice:
    """One measurement choice a rule leaves open: the keyword an experiment's measure function takes."""

    name: str
    """The keyword, e.g. 'final_share'."""
    values: tuple
    """Its defensible range; the first is the default every claim's measured value is shown at."""
    labels: tuple
    """How a verdict names each value."""

    def text(self, value) -> str:
        return self.labels[self.values.index(value)]


FINAL_SHARE = Choice("final_share", (0.1, 0.05, 0.2),
                     ("final values over the last tenth", "final values over the last twentieth",
                      "final values over the last fifth"))
TOLERANCE = Choice("tolerance", (0.05, 0.03, 0.10, 0.15),
                   ("tolerance 5 %", "tolerance 3 %", "tolerance 10 %", "tolerance 15 %"))
BLOCKS = Choice("blocks", (1, 2, 4), ("the stored blocks", "blocks twice as wide", "blocks four times as wide"))
ZERO_LEVEL = Choice("zero_level", (0.05, 0.02, 0.1),
                    ("one collision per 20 episodes", "one collision per 50 episodes", "one collision per 10 episodes"))
DRAWN = Choice("drawn", (1.0, 0.1), ("the whole run drawn", "its first tenth drawn"))
READ = Choice("read", (1.0, 0.5, 0.1), ("the drawn run read whole", "its first half read", "its first tenth read"))
STUCK = Choice("stuck_threshold", (0.5, 0.3, 0.7), ("stuck below P(L) 0.5", "stuck below P(L) 0.3", "stuck below P(L) 0.7"))


@dataclass(frozen=True)
class Rule:
    """One kind of sentence of the chapter and how a claim of that kind is judged (docs/verdicts.md)."""

    key: str
    sentence: str
    """The kind of sentence, e.g. 'X outperforms Y on a learning curve'."""
    read_on: str
    """Where the metric is read: 'learning curves', 'greedy policy', 'learned parameters' or 'exact'."""
    metrics: str
    """A pattern every metric of the rule's family matches (the claim's ``metric``)."""
    choices: tuple = ()
    """The measurement choices (:class:`Choice`) its claims are judged over."""

    def takes(self, metric: str) -> bool:
        return re.search(self.metrics, metric) is not None


RULES = {rule.key: rule for rule in (
    Rule("curve_lead", "X outperforms, beats or clearly does worse than Y", "learning curves", r"_mean_visible$",
         (DRAWN, READ)),
    Rule("not_behind_at_end", "X is not behind Y at the end (a weaker reading)", "learning curves", r"_final_high$"),
    Rule("learns_faster", "X learns faster than Y", "learning curves", r"_reach_ratio_high$", (TOLERANCE,)),
    Rule("converges_faster", "X converges faster than Y", "learning curves", r"^convergence_\w+_over_\w+$",
         (TOLERANCE, BLOCKS)),
    Rule("final_gap", "X converges to a better solution than Y", "learning curves",
         r"^steps_\w+_minus_\w+$|_over_elsewhere_min$", (FINAL_SHARE,)),
    Rule("almost_as_good", "X is almost as good as Y", "learning curves", r"^reward_\w+_over_\w+$", (FINAL_SHARE,)),
    Rule("almost_as_good_greedy", "X's solution is almost as good as Y's", "greedy policy",
         r"^greedy_reward_\w+_over_\w+$"),
    Rule("much_more", "X is much better than Y", "learning curves", r"^reward_\w+_minus_\w+$", (FINAL_SHARE,)),
    Rule("about_n", "X converges to about N, or to at most about N", "learning curves",
         r"_off_\d+$|^reward_independent$", (FINAL_SHARE,)),
    Rule("level_on_curve", "X reaches zero, or keeps above a level, while it learns", "learning curves",
         r"^collisions_\w+$", (FINAL_SHARE,)),
    Rule("level_greedy", "X finds a solution with zero collisions", "greedy policy",
         r"^greedy_solution_collisions_\w+$"),
    Rule("level_fast", "X reaches a level relatively fast, or never", "learning curves",
         r"^zero_collisions_after_\w+$", (ZERO_LEVEL,)),
    Rule("learned_mapping", "a learner's units learn a mapping", "learned parameters",
         r"_share_two_observe$|^marked_\w+_cq$"),
    Rule("approximates_region", "a structure approximates a region", "learned parameters",
         r"_share_of_ceiling$|^region_I_error_removed$|^grid_prob_\w+$"),
    Rule("near_best", "X is as good as the best X could be", "learned parameters", r"_gap$|_line_reward$"),
    Rule("depends_on", "an outcome depends on Z, or Z decides it", "learned parameters",
         r"^init_share_of_outcome_\w+$", (STUCK,)),
    Rule("raises_frequency", "raising a setting makes an outcome happen more often", "learned parameters",
         r"^stuck_fraction_rise$", (STUCK,)),
    Rule("growth", "a size grows linearly, polynomially or exponentially", "exact",
         r"^loglog_slope_\w+$|^growth_factor_\w+$|^largest_n_\w+$"),
    Rule("size_comparison", "X stores the same as, fewer than or far more than Y", "exact",
         r"^parameters_\w+$|^q_entries_\w+$"),
    Rule("exact_property", "a property of the map", "exact", r"^selfish_collisions$|^optimal_collisions$"),
)}
"""Every rule of docs/verdicts.md, by key."""
