"""Seeds by name (glamas.seeds): every (master seed, study, case, learner) of the chapter's
gridworld experiment and of the studies beyond the chapter gets streams of its own, enumerated over
a grid larger than the committed runs."""

import itertools

import pytest

from glamas import cli, seeds
from glamas.errors import UserError
from glamas.experiments import benchmark_maps as bm
from glamas.experiments import gridworld as gw
from glamas.experiments import scaling as sc
from glamas.experiments import warehouses as wh
from glamas.learners import registry

LEARNERS = tuple(registry.LEARNERS)
MASTER_SEEDS = range(4)


def _chapter_grid():
    """The gridworld experiment's seeds per learner, and the line world's per experiment (as
    glamas.experiments.single_gla and and_network name them)."""
    gridworld = {("gridworld", seed, name): gw.seed_of(seed, name) for seed, name in itertools.product(range(256), LEARNERS)}
    return {**gridworld, **{(name, seed): seeds.named(seed, name) for seed in range(256)
                            for name in ("single_gla", "and_network")}}


def _scaling_grid():
    return {("scaling", seed, n, name): sc.seed_of(seed, name, n)
            for seed, n, name in itertools.product(MASTER_SEEDS, range(1, 257), LEARNERS)}


def _benchmark_grid():
    maps = sorted(set(bm.BenchmarkConfig().maps) | set(bm.FIELD_MAPS))
    return {("benchmark", seed, map_name, name): seeds.named(*bm.case_names(seed, map_name), name)
            for seed, map_name, name in itertools.product(MASTER_SEEDS, maps, LEARNERS)}


def _warehouses_grid():
    return {("warehouses", *key): wh.seed_of(*key)
            for key in itertools.product(MASTER_SEEDS, ("chapter", "field"), (8, 32, 128), range(16), LEARNERS)}


def test_every_run_of_every_study_has_its_own_streams():
    grid = {**_chapter_grid(), **_scaling_grid(), **_benchmark_grid(), **_warehouses_grid()}
    assert len(set(grid.values())) == len(grid)
    assert max(grid.values()) < 2 ** 48  # below the evaluations' seeds


def test_the_arithmetic_key_collision_is_gone():
    """16 seed + N gave seed 1 with one agent the streams of seed 0 with 17 agents."""
    assert sc.seed_of(1, "independent", 1) != sc.seed_of(0, "independent", 17)


def test_a_name_is_its_words_in_order():
    assert seeds.named(0, "scaling", 8, "mmdp") == seeds.named(0, "scaling", 8, "mmdp")
    assert seeds.named(0, "scaling", 8, "mmdp") != seeds.named(0, 8, "scaling", "mmdp")


def test_names_that_differ_by_trailing_zeros_cannot_be_given():
    """SeedSequence pads with zeros: (7,) and (7, 0) would name one seed; a list ends with a string."""
    for names in ((7,), (7, 0), ()):
        with pytest.raises(UserError, match="must end with a string"):
            seeds.named(*names)


def test_the_largest_seed_of_the_command_line_is_one_word():
    """A name of 2**32 or more would be split into two 32-bit words and could spell another list."""
    assert seeds.named(cli.MAX_SEED, "gridworld") != seeds.named(0, "gridworld")
    with pytest.raises(UserError, match=r"integers in \[0, 2\*\*32\) and strings"):
        seeds.named(cli.MAX_SEED + 1, "gridworld")


@pytest.mark.parametrize("names", [(-1, "scaling"), (0.5, "scaling"), (None, "scaling"), (True, "scaling")])
def test_a_name_that_is_no_integer_or_string_is_refused(names):
    with pytest.raises(UserError, match=r"integers in \[0, 2\*\*32\) and strings"):
        seeds.named(*names)
