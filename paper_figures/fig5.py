"""Fig. 5: experiment 1's regions (a) and the lines a typical run of single GLAs learns (b)."""

import matplotlib

matplotlib.use("Agg")

from glamas import cli, plotting  # noqa: E402
from glamas.experiments import single_gla  # noqa: E402


@cli.guard
def main(argv=None):
    defaults = single_gla.SingleGLAConfig()
    parser = cli.figure_parser(__doc__.splitlines()[0], runs=defaults.runs, iterations=defaults.iterations)
    args = cli.parse(parser, argv)
    config = single_gla.SingleGLAConfig(iterations=args.iterations, runs=args.runs,
                                        record_points=min(defaults.record_points, args.iterations))
    result = cli.run_experiment(args, "fig5", config, single_gla.run)

    fig, (ax_a, ax_b) = plotting.new_figure(8.0, 4.0, ncols=2)
    single_gla.plot_regions(ax_a)
    ax_a.set_title("(a) regions and rewarded joint actions")
    run_index = single_gla.typical_run(result)
    single_gla.plot_learned_lines(ax_b, result, run_index)
    ax_b.set_title(f"(b) learned lines (typical run {run_index})")
    for path in cli.write_outputs(args, "fig5", fig, config, result.arrays()):
        print(path)


if __name__ == "__main__":
    main()
