"""Scaling study: learned values per run against the number of agents (Table 1 measured)."""

from glamas import cli
from glamas.experiments import scaling


@cli.guard
def main(argv=None):
    scaling.figure_main("scaling_sizes", "Scaling study: Q-table entries and GLA parameters per run "
                        "for 2 to 6 agents, measured where the tables fit the memory budget", argv)


if __name__ == "__main__":
    main()
