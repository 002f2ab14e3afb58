"""Related work on TunnelToGoal: collisions per episode (as Fig. 12a), sparse tabular MAQ and CQ-learning added."""

from glamas import errors, figures
from glamas.experiments import gridworld, related_work


def main(argv=None):
    with figures.figure(related_work.EXPERIMENT, "related_collisions", __doc__, argv,
                        size=(6.0, 5.0)) as (ax, result, config):
        related_work.plot_curve(ax, result, config, gridworld.plot_collisions)


if __name__ == "__main__":
    errors.run(main)
