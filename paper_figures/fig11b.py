"""Fig. 11b: reward per episode of the four gridworld learners (chapter Section 5.3)."""

from glamas import cli
from glamas.experiments import gridworld


@cli.guard
def main(argv=None):
    gridworld.figure_main("fig11b", "Fig. 11b: reward per episode of the four gridworld learners", argv)


if __name__ == "__main__":
    main()
