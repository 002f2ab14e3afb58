"""Related work on TunnelToGoal: steps on which the agents observe each other of independent, MMDP, 2observe, sparse tabular MAQ and
CQ-learning (Fig. 11/12-style comparison, beyond the chapter)."""

from glamas import cli
from glamas.experiments import related_work


@cli.guard
def main(argv=None):
    related_work.figure_main("related_coordinations", "Related work on TunnelToGoal: steps on which the agents observe each other", argv)


if __name__ == "__main__":
    main()
