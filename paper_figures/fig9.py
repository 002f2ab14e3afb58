"""Fig. 9: the gridworld of Section 5.3 (TunnelToGoal)."""

from glamas import errors, figures
from glamas.gridworld import draw, tunnel_to_goal


def main(argv=None):
    with figures.fixed_figure("fig9", __doc__, argv, size=(3.2, 3.2)) as ax:
        draw.draw_map(ax, tunnel_to_goal())


if __name__ == "__main__":
    errors.run(main)
