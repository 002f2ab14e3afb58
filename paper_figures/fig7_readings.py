"""Fig. 7b under the other two parabolas of region I: probability of the optimal action L in region I.

The chapter does not state region I's parabola; ours is x2 >= x1^2 - 0.5 (Fig. 7b). Fig. 7's
claims are judged under these two as well (docs/ledger.md).
"""

from glamas import errors, figures
from glamas.experiments import and_network


def main(argv=None):
    with figures.figure(and_network.FIG7_READINGS, "fig7_readings", __doc__, argv, size=(12.0, 5.0),
                        ncols=2) as (axes, readings, _):
        for ax, (name, result) in zip(axes, readings.items()):
            and_network.plot_prob_left(ax, result)
            ax.set_title(f"region I: {name}\n{ax.get_title()}", fontsize="medium")


if __name__ == "__main__":
    errors.run(main)
