"""Fig. 6: average reward of single GLAs with the joint, absolute-distance and deictic contexts.

Left, as the chapter draws it: the average feedback per window of iterations. Right: the expected
reward of the GLA parameters at log-spaced checkpoints, exact on the evaluation grid, which shows
the start of learning that the left panel compresses into its first windows.
"""

from glamas import errors, figures
from glamas.experiments import single_gla, state_encoding


def main(argv=None):
    with figures.figure(state_encoding.FIG6, "fig6", __doc__, argv, size=(11.0, 4.0), ncols=2) as (axes, results, _):
        single_gla.plot_reward_curves(axes[0], results)
        axes[0].set_title("(a) as the chapter draws it: average reward per window", fontsize="medium")
        state_encoding.plot_expected_curves(axes[1], results)
        axes[1].set_title("(b) expected reward at each checkpoint (log axis)", fontsize="medium")


if __name__ == "__main__":
    errors.run(main)
