"""Fig. 7 (what the chapter only states): fraction of runs stuck in 'R everywhere' as region II's reward rises."""

import matplotlib

matplotlib.use("Agg")

from glamas import cli, plotting  # noqa: E402
from glamas.experiments import and_network  # noqa: E402


@cli.guard
def main(argv=None):
    defaults = and_network.ANDNetworkConfig()
    parser = cli.figure_parser(__doc__.splitlines()[0], runs=defaults.runs, iterations=defaults.iterations)
    args = cli.parse(parser, argv)
    config = and_network.ANDNetworkConfig(iterations=args.iterations, runs=args.runs,
                                          record_points=min(defaults.record_points, args.iterations))
    result = cli.run_experiment(args, "fig7_sweep", config, and_network.sweep)

    fig, ax = plotting.new_figure(6.0, 4.0)
    and_network.plot_stuck_fraction(ax, result)
    for path in cli.write_outputs(args, "fig7_sweep", fig, config, result.arrays()):
        print(path)


if __name__ == "__main__":
    main()
