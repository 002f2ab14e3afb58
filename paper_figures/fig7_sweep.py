"""Fig. 7 (what the chapter only states): fraction of runs stuck in 'R everywhere' as region II's reward rises."""

from glamas import errors, figures
from glamas.experiments import and_network


def main(argv=None):
    with figures.figure(and_network.FIG7_SWEEP, "fig7_sweep", __doc__, argv) as (ax, result, _):
        and_network.plot_stuck_fraction(ax, result)


if __name__ == "__main__":
    errors.run(main)
