"""Related work on TunnelToGoal: collisions per episode of independent, MMDP, 2observe, sparse tabular MAQ and
CQ-learning (Fig. 11/12-style comparison, beyond the chapter)."""

from glamas import cli
from glamas.experiments import related_work


@cli.guard
def main(argv=None):
    related_work.figure_main("related_collisions", "Related work on TunnelToGoal: collisions per episode", argv)


if __name__ == "__main__":
    main()
