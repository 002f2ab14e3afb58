"""Fig. 10 readings (beyond the chapter): 2observe under each reading of its lost GLA feedback."""

from glamas import errors, figures
from glamas.experiments import fig10_readings, gridworld


def main(argv=None):
    with figures.figure(fig10_readings.EXPERIMENT, "fig10_readings", __doc__, argv, size=(12.0, 5.0), ncols=2,
                        claims=gridworld.curve_collision_claims()) as ((coordination, collisions), result, config):
        rows = fig10_readings.summary(result, config)
        fig10_readings.plot_coordination(coordination, rows)
        fig10_readings.plot_collisions(collisions, rows)


if __name__ == "__main__":
    errors.run(main)
