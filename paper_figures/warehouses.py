"""Many agents against a plan: on 16 generated warehouses per N, the share of agents each learner's greedy policy brings in (ISR, top) and of episodes in which every agent is in (CSR, bottom), under the chapter's rewards (left) and the field's (right); a plan brings every agent in (ISR and CSR 1)."""

from glamas import errors, figures, plotting
from glamas.experiments import warehouses


def main(argv=None):
    with figures.figure(warehouses.EXPERIMENT, "warehouses", __doc__, argv, size=(11.0, 8.0), nrows=2,
                        ncols=2) as (axes, result, _):
        warehouses.plot_greedy(axes[0], result, "isr")
        warehouses.plot_greedy(axes[1], result, "csr")
        plotting.legend_below_figure(axes[1, 0], ncols=3)


if __name__ == "__main__":
    errors.run(main)
