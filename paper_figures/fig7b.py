"""Fig. 7b: probability of the optimal action L in region I for both AND-network agents."""

from glamas import errors, figures
from glamas.experiments import and_network


def main(argv=None):
    with figures.figure(and_network.FIG7, "fig7b", __doc__, argv) as (ax, result, _):
        and_network.plot_prob_left(ax, result)


if __name__ == "__main__":
    errors.run(main)
