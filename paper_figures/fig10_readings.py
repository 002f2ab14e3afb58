"""Fig. 10 readings (beyond the chapter): 2observe under each reading of its lost GLA feedback."""

from glamas.experiments import fig10_readings


def main(argv=None):
    fig10_readings.figure_main(argv)


if __name__ == "__main__":
    main()
