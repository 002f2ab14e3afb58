"""Fig. 10 (reconstructed): the feedback table of 2observe's GLAs (chapter Section 5.3)."""

from glamas import errors, figures
from glamas.experiments import gridworld


def main(argv=None):
    with figures.fixed_figure("fig10", __doc__, argv, size=(6.0, 2.2)) as ax:
        gridworld.plot_feedback_table(ax, gridworld.GridworldConfig())


if __name__ == "__main__":
    errors.run(main)
