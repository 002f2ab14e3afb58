"""Related work on TunnelToGoal: Q entries per agent (measured) against the final reward of
independent, MMDP, 2observe, sparse tabular MAQ and CQ-learning (beyond the chapter)."""

from glamas import cli
from glamas.experiments import related_work


@cli.guard
def main(argv=None):
    related_work.figure_main("related_sizes", "Related work on TunnelToGoal: Q entries per agent (measured) against final reward", argv)


if __name__ == "__main__":
    main()
