"""Related work on TunnelToGoal: steps from start to goal of independent, MMDP, 2observe, sparse tabular MAQ and
CQ-learning (Fig. 11/12-style comparison, beyond the chapter)."""

from glamas import cli
from glamas.experiments import related_work


@cli.guard
def main(argv=None):
    related_work.figure_main("related_steps", "Related work on TunnelToGoal: steps from start to goal", argv)


if __name__ == "__main__":
    main()
