"""Fig. 12b: coordinations per episode of 2observe (chapter Section 5.3)."""

from glamas import cli
from glamas.experiments import gridworld


@cli.guard
def main(argv=None):
    gridworld.figure_main("fig12b", "Fig. 12b: coordinations per episode of 2observe", argv)


if __name__ == "__main__":
    main()
