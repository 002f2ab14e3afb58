"""Fig. 10 (reconstructed): the feedback table of 2observe's GLAs (chapter Section 5.3)."""

from glamas import cli
from glamas.experiments import gridworld


@cli.guard
def main(argv=None):
    gridworld.figure_main("fig10", "Fig. 10 (reconstructed): the feedback table of 2observe's GLAs", argv)


if __name__ == "__main__":
    main()
