"""Scaling study: Q-table entries and GLA parameters per run for 2 to 6 agents, measured where the
tables fit the memory budget (Table 1 measured)."""

from glamas import errors, figures
from glamas.experiments import scaling


def main(argv=None):
    with figures.figure(scaling.EXPERIMENT, "scaling_sizes", __doc__, argv,
                        size=(8.0, 4.5)) as (ax, result, config):
        scaling.plot_sizes(ax, result, config)


if __name__ == "__main__":
    errors.run(main)
