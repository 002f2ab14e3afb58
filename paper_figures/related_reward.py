"""Related work on TunnelToGoal: reward per episode (as Fig. 11b), sparse tabular MAQ and CQ-learning added."""

from glamas import errors, figures
from glamas.experiments import gridworld, related_work


def main(argv=None):
    with figures.figure(related_work.EXPERIMENT, "related_reward", __doc__, argv) as (ax, result, config):
        related_work.plot_curve(ax, result, config, gridworld.plot_reward)


if __name__ == "__main__":
    errors.run(main)
