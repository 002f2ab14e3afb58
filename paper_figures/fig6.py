"""Fig. 6: average reward of single GLAs with the joint, absolute-distance and deictic contexts."""

from glamas.experiments import single_gla


def main(argv=None):
    with single_gla.FIG6.figure("fig6", __doc__, argv) as (ax, results, _):
        single_gla.plot_reward_curves(ax, results)


if __name__ == "__main__":
    main()
