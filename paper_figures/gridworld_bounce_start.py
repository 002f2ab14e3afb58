"""Fig. 11a and 12a under the chapter's literal bounce: collided agents go back to their start cell.

Sec. 5.3 says a collided agent "is bounced back to its original position"; the experiment's default
reading puts it back in the cell it came from, as re-implementations do. Left, steps to the goal;
right, collisions per episode of the four learners with the start-cell bounce. The Section 5.3
claims are judged under this reading as well (docs/ledger.md).
"""

from glamas import errors, figures
from glamas.experiments import gridworld


def main(argv=None):
    with figures.figure(gridworld.BOUNCE_START, "gridworld_bounce_start", __doc__, argv, size=(12.0, 4.5),
                        ncols=2) as (axes, result, config):
        gridworld.plot_steps(axes[0], result, gridworld.optimum(config))
        gridworld.plot_collisions(axes[1], result, gridworld.optimum(config))


if __name__ == "__main__":
    errors.run(main)
