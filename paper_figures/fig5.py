"""Fig. 5: experiment 1's regions (a) and the lines a typical run of single GLAs learns (b)."""

from glamas import errors, figures
from glamas.experiments import single_gla


def main(argv=None):
    with figures.figure(single_gla.FIG5, "fig5", __doc__, argv, size=(8.0, 4.0),
                        ncols=2) as ((regions, lines), result, _):
        single_gla.plot_regions(regions)
        regions.set_title("(a) regions and rewarded joint actions", pad=10)
        typical = single_gla.typical_run(result)
        single_gla.plot_learned_lines(lines, result, typical)
        lines.set_title(f"(b) learned lines (typical run {typical})", pad=10)


if __name__ == "__main__":
    errors.run(main)
