"""Scaling study: final steps, reward, collisions and convergence against the number of agents."""

from glamas import cli
from glamas.experiments import scaling


@cli.guard
def main(argv=None):
    scaling.figure_main("scaling_performance", "Scaling study: final steps to goal, reward, collisions "
                        "and episodes to converge for 2 to 6 agents", argv)


if __name__ == "__main__":
    main()
