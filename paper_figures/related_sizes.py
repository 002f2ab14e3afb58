"""Related work on TunnelToGoal: Q entries per agent (measured) against the final reward of
independent, MMDP, 2observe, sparse tabular MAQ and CQ-learning (beyond the chapter)."""

from glamas import errors, figures
from glamas.experiments import related_work


def main(argv=None):
    with figures.figure(related_work.EXPERIMENT, "related_sizes", __doc__, argv,
                        size=(8.0, 4.0)) as (ax, result, config):
        related_work.plot_size_and_reward(ax, result, config)


if __name__ == "__main__":
    errors.run(main)
