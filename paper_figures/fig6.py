"""Fig. 6: average reward of single GLAs with the joint, absolute-distance and deictic contexts."""

import matplotlib

matplotlib.use("Agg")

from glamas import cli, plotting  # noqa: E402
from glamas.experiments import single_gla  # noqa: E402


@cli.guard
def main(argv=None):
    defaults = single_gla.SingleGLAConfig()
    parser = cli.figure_parser(__doc__.splitlines()[0], runs=defaults.runs, iterations=defaults.iterations)
    args = cli.parse(parser, argv)
    config = single_gla.SingleGLAConfig(iterations=args.iterations, runs=args.runs, L=single_gla.FIG6_L,
                                        record_points=min(defaults.record_points, args.iterations))
    results = cli.run_experiment(args, "fig6", config, single_gla.compare_encodings,
                                 copies=len(single_gla.ENCODING_NAMES))

    fig, ax = plotting.new_figure(6.0, 4.0)
    single_gla.plot_reward_curves(ax, results)
    for path in cli.write_outputs(args, "fig6", fig, config, single_gla.encoding_arrays(results)):
        print(path)


if __name__ == "__main__":
    main()
