"""Fig. 11a: steps from start to goal of the four gridworld learners (chapter Section 5.3)."""

from glamas.experiments import gridworld


def main(argv=None):
    gridworld.figure_main("fig11a", "Fig. 11a: steps from start to goal of the four gridworld learners", argv)


if __name__ == "__main__":
    main()
