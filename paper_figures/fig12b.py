"""Fig. 12b: coordinations per episode of 2observe (chapter Section 5.3)."""

from glamas import errors, figures
from glamas.experiments import gridworld


def main(argv=None):
    with figures.figure(gridworld.EXPERIMENT, "fig12b", __doc__, argv) as (ax, result, _):
        gridworld.plot_coordinations(ax, result)


if __name__ == "__main__":
    errors.run(main)
