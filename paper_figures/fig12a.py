"""Fig. 12a: collisions per episode of the four gridworld learners (chapter Section 5.3)."""

from glamas import errors, figures
from glamas.experiments import gridworld


def main(argv=None):
    with figures.figure(gridworld.EXPERIMENT, "fig12a", __doc__, argv,
                        claims=gridworld.curve_collision_claims()) as (ax, result, config):
        gridworld.plot_collisions(ax, result, gridworld.optimum(config))


if __name__ == "__main__":
    errors.run(main)
