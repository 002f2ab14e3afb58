"""Fig. 6 under the other two readings of its box L: expected reward of each context encoding.

The chapter does not restate Fig. 6's box (eq. 14). Left, every encoding at L = 2; right, each
encoding's box scaled with its largest input (Fig. 5's L times 1 for the joint location, 2 for the
absolute and deictic distances). Fig. 6's claims are judged under both as well (docs/ledger.md).
"""

from glamas import errors, figures
from glamas.experiments import state_encoding


BOX_WORDS = {"fig5": "box L of Fig. 5 for every encoding", "two": "box L = 2 for every encoding",
             "input_range": "box L scaled with each encoding's largest input"}
"""Each reading of the box (glamas.experiments.state_encoding.BOX_READINGS) in words."""


def main(argv=None):
    with figures.figure(state_encoding.FIG6_READINGS, "fig6_readings", __doc__, argv, size=(11.0, 4.0),
                        ncols=2) as (axes, readings, _):
        for ax, (box, results) in zip(axes, readings.items()):
            state_encoding.plot_expected_curves(ax, results)
            ax.set_title(BOX_WORDS[box], fontsize="medium")


if __name__ == "__main__":
    errors.run(main)
