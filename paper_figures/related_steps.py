"""Related work on TunnelToGoal: steps to the goal (as Fig. 11a), sparse tabular MAQ and CQ-learning added."""

from glamas import errors, figures
from glamas.experiments import gridworld, related_work


def main(argv=None):
    with figures.figure(related_work.EXPERIMENT, "related_steps", __doc__, argv) as (ax, result, config):
        related_work.plot_curve(ax, result, config, gridworld.plot_steps)


if __name__ == "__main__":
    errors.run(main)
